// Spinning-radar polar scans and their decoders (paper Sec. III-D, Eq. 8).
// One row per azimuth, one column per range bin; bin i covers range i * range_resolution.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace coral_introspection {
namespace radar {

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

// Whether the valid rows of a decoded scan are one sweep of a spinning radar, checked
// before a scan is scored (corrupt rows must give no verdict rather than a wrong one):
// - row stamps finite, non-decreasing, and last - first <= 1.5 scan_period;
// - azimuths advancing in one direction (modulo 2 pi) by more than 0 and at most a quarter
//   turn from one valid row to the next (a stuck encoder does not advance);
// - together covering at least 90 % of a turn (span plus one mean step) without wrapping
//   past a full turn.
// Returns false with a message naming the offending row(s). scan_period [s] >= 0.
bool checkSweep(const PolarScan& scan, double scan_period, std::string* error);

// Oxford layout (400 x 3779 mono8): cols 0-7 int64 LE timestamp [us], cols 8-9 uint16 LE
// encoder (azimuth = value / 5600 * 2 pi), col 10 valid flag (255), cols 11.. 3768 range bins.
// The azimuth is used as is: with x = r cos(a), y = r sin(a) the dataset's GT radar odometry
// is consistent (checked on the data, see README "Radar front end"). Rows whose flag is not
// 255, whose encoder value is >= 5600 or whose stamp is <= 0 are marked invalid.
// scan.stamp = first valid row's time (equals the PNG file name). Fails (with a message) on
// wrong size/type, no valid row, or valid rows that are not one sweep (checkSweep with the
// CTS350-X period of 0.25 s): reversed or corrupt row stamps, a stuck encoder.
// Both decoders: out->power is a view of the input's buffer (no copy); keep the input alive
// (or clone) while the scan is used.
bool decodeOxfordImage(const cv::Mat& img, PolarScan* out, std::string* error);
bool loadOxfordScan(const std::string& png_path, PolarScan* out, std::string* error);

// Plain mono8 image with cfg: row i has azimuth offset + 2 pi i / rows (ccw) or
// offset - 2 pi i / rows (cw) and time stamp + i * scan_period / rows; scan.stamp = stamp.
bool decodePolarImage(const cv::Mat& mono8, const PolarImageConfig& cfg, double stamp,
                      PolarScan* out, std::string* error);

}  // namespace radar
}  // namespace coral_introspection
