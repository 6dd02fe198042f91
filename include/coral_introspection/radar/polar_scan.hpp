// Spinning-radar polar scans and their decoders (paper Sec. III-D, Eq. 8).
// One row per azimuth, one column per range bin; bin i covers range i * range_resolution.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace coral_introspection {
namespace core {

enum class AzimuthDirection { kCounterClockwise, kClockwise };

struct PolarScan {
  cv::Mat power;                     // CV_8UC1, one row per azimuth, one column per range bin
                                     // (bin 0 = range 0)
  std::vector<double> azimuths;      // [rad] per row, sensor frame, counter-clockwise from +x
                                     // (after direction/offset)
  std::vector<double> stamps;        // [s] per row (absolute time)
  std::vector<uint8_t> valid;        // per row, 0 = row skipped
  double range_resolution = 0.0432;  // [m per bin] (gamma of Eq. 8)
  double stamp = 0.0;                // [s] reference time of the scan (motion compensation target)
};

// A plain mono8 polar image: rows = azimuths, columns = range bins (after first_data_column).
struct PolarImageConfig {
  double range_resolution = 0.0432;  // [m per bin]
  int first_data_column = 0;         // columns before it are metadata, ignored
  int num_azimuths = 400;            // rows expected; 0 accepts any row count
  // Whether the azimuth grows (ccw) or shrinks (cw) with the row index, in the sensor frame
  // whose x = r cos(a), y = r sin(a) points are produced.
  AzimuthDirection direction = AzimuthDirection::kCounterClockwise;
  double azimuth_offset_rad = 0.0;  // [rad] azimuth of row 0 in the sensor frame
  double scan_period = 0.25;        // [s] one revolution, to timestamp rows

  // Navtech CTS350-X (Oxford Radar RobotCar), 400 azimuths, 0.0432 m, 4 Hz.
  static PolarImageConfig oxfordCts350x();
  // Navtech CIR204 (MulRan, Boreas), 400 azimuths, 0.0595 m, 4 Hz.
  static PolarImageConfig mulranCir204();
  std::string validate() const;  // empty when valid
};

// Oxford layout (400 x 3779 mono8): cols 0-7 int64 LE timestamp [us], cols 8-9 uint16 LE
// encoder (azimuth = value / 5600 * 2 pi), col 10 valid flag (255), cols 11.. 3768 range bins.
// The azimuth is used as is: with x = r cos(a), y = r sin(a) the dataset's GT radar odometry
// is consistent (checked on the data, see README "Radar front end"). Rows whose flag is not
// 255 or whose encoder value is >= 5600 are marked invalid. scan.stamp = first row's time
// (equals the PNG file name). Fails (with a message) on wrong size/type or no valid row.
// Both decoders: out->power is a view of the input's buffer (no copy); keep the input alive
// (or clone) while the scan is used.
bool decodeOxfordImage(const cv::Mat& img, PolarScan* out, std::string* error);
bool loadOxfordScan(const std::string& png_path, PolarScan* out, std::string* error);

// Plain mono8 image with cfg: row i has azimuth offset + 2 pi i / rows (ccw) or
// offset - 2 pi i / rows (cw) and time stamp + i * scan_period / rows; scan.stamp = stamp.
bool decodePolarImage(const cv::Mat& mono8, const PolarImageConfig& cfg, double stamp,
                      PolarScan* out, std::string* error);

}  // namespace core
}  // namespace coral_introspection
