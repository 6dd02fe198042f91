#include "coral_introspection/radar/polar_scan.hpp"

#include "coral_introspection/coral/validation.hpp"

#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

namespace coral_introspection {
namespace radar {

namespace {
constexpr int kOxfordRows = 400;
constexpr int kOxfordCols = 3779;
constexpr int kOxfordMeta = 11;  // 8 stamp + 2 encoder + 1 valid flag
constexpr double kOxfordEncoderSize = 5600.0;

// One sweep of a spinning radar (checkSweep). The CTS350-X sweeps of the Oxford data span
// 0.247-0.253 s at a nominal 0.25 s; 1.5 periods leaves room for jitter, not for a second
// sweep or a corrupt stamp.
constexpr double kMaxSweepPeriods = 1.5;
constexpr double kMinCoverageTurns = 0.9;  // of 2 pi: a few missing rows, not a half sweep
constexpr double kMaxStepTurns = 0.25;     // between consecutive valid rows

std::string rowStamp(int row, double t) {
  std::ostringstream s;
  s.precision(17);
  s << "row " << row << " (" << t << " s)";
  return s.str();
}

std::string typeName(const cv::Mat& m) {
  std::ostringstream s;
  s << "depth " << m.depth() << ", " << m.channels() << " channel(s)";
  return s.str();
}
}  // namespace

PolarImageConfig PolarImageConfig::oxfordCts350x() {
  PolarImageConfig c;
  c.range_resolution = 0.0432;
  c.first_data_column = kOxfordMeta;  // also decodes the raw Oxford layout (metadata ignored)
  c.num_azimuths = kOxfordRows;
  c.direction = AzimuthDirection::kCounterClockwise;  // encoder angle grows with the row
  c.azimuth_offset_rad = 0.0;
  c.scan_period = 0.25;  // 4 Hz
  return c;
}

PolarImageConfig PolarImageConfig::mulranCir204() {
  PolarImageConfig c;
  c.range_resolution = 0.0595;
  c.first_data_column = 0;
  c.num_azimuths = 400;
  c.direction = AzimuthDirection::kCounterClockwise;  // same Navtech encoder convention
  c.azimuth_offset_rad = 0.0;
  c.scan_period = 0.25;  // 4 Hz
  return c;
}

std::string PolarImageConfig::validate() const {
  return coral::Problems()
      .require(range_resolution > 0.0 && range_resolution < 10.0, "range_resolution",
               "in (0, 10) m per bin", range_resolution)
      .require(first_data_column >= 0, "first_data_column", ">= 0", first_data_column)
      .require(num_azimuths >= 0, "num_azimuths", ">= 0 (0 = any)", num_azimuths)
      .require(std::isfinite(azimuth_offset_rad), "azimuth_offset_rad", "finite",
               azimuth_offset_rad)
      .require(scan_period >= 0.0 && scan_period < 10.0, "scan_period", "in [0, 10) s", scan_period)
      .str();
}

bool checkSweep(const PolarScan& scan, double scan_period, std::string* error) {
  const std::size_t n = scan.valid.size();
  if (scan.azimuths.size() != n || scan.stamps.size() != n)
    return coral::fail(error, "polar scan: azimuths/stamps/valid sizes differ");
  const double max_duration = kMaxSweepPeriods * scan_period;
  int first = -1, prev = -1, num_valid = 0;
  double direction = 0.0, turned = 0.0;  // sign of the rotation, total angle [rad]
  for (std::size_t i = 0; i < n; ++i) {
    if (!scan.valid[i]) continue;
    const int row = static_cast<int>(i);
    const double t = scan.stamps[i], a = scan.azimuths[i];
    if (!std::isfinite(t) || !std::isfinite(a))
      return coral::fail(error,
                         "polar scan " + rowStamp(row, t) + " has a non-finite stamp or azimuth");
    ++num_valid;
    if (first < 0) {
      first = prev = row;
      continue;
    }
    if (t < scan.stamps[prev])
      return coral::fail(error, "polar scan row stamps go backwards: " + rowStamp(row, t) +
                                    " is before " + rowStamp(prev, scan.stamps[prev]));
    if (t - scan.stamps[first] > max_duration)
      return coral::fail(error, "polar scan rows span more than one sweep: " + rowStamp(row, t) +
                                    " is more than " + std::to_string(max_duration) + " s after " +
                                    rowStamp(first, scan.stamps[first]));
    // Azimuth step to this row, wrapped into [-pi, pi]: its sign is the spin direction.
    const double step = std::remainder(a - scan.azimuths[prev], 2.0 * M_PI);
    if (direction == 0.0 && step != 0.0) direction = step > 0.0 ? 1.0 : -1.0;
    if (!(step * direction > 0.0) || std::abs(step) > kMaxStepTurns * 2.0 * M_PI) {
      std::ostringstream e;
      e << "polar scan azimuth " << (step == 0.0 ? "does not advance (stuck encoder?)" : "jumps")
        << " from row " << prev << " (" << scan.azimuths[prev] << " rad) to row " << row << " ("
        << a << " rad)";
      return coral::fail(error, e.str());
    }
    turned += std::abs(step);
    prev = row;
  }
  if (num_valid == 0) return coral::fail(error, "polar scan has no valid row");
  // Span of the rows plus one mean step: 2 pi for a complete sweep of evenly spaced rows.
  const double coverage = num_valid > 1 ? turned * num_valid / (num_valid - 1) : 0.0;
  if (coverage < kMinCoverageTurns * 2.0 * M_PI || turned >= 2.0 * M_PI) {
    std::ostringstream e;
    e << "polar scan azimuths cover " << coverage / (2.0 * M_PI) << " turns over " << num_valid
      << " valid rows, expected one sweep (at least " << kMinCoverageTurns
      << ", under 1 turn between the first and last row)";
    return coral::fail(error, e.str());
  }
  return true;
}

bool decodeOxfordImage(const cv::Mat& img, PolarScan* out, std::string* error) {
  if (out == nullptr) return coral::fail(error, "decodeOxfordImage: null output");
  if (img.empty()) return coral::fail(error, "Oxford radar image is empty");
  if (img.type() != CV_8UC1)
    return coral::fail(
        error, "Oxford radar image must be 8-bit single channel (mono8), got " + typeName(img));
  if (img.rows != kOxfordRows || img.cols != kOxfordCols)
    return coral::fail(error, "Oxford radar image must be 400 x 3779 (rows x cols), got " +
                                  std::to_string(img.rows) + " x " + std::to_string(img.cols));
  const int n = img.rows;
  out->azimuths.assign(n, 0.0);
  out->stamps.assign(n, 0.0);
  out->valid.assign(n, 0);
  out->range_resolution = 0.0432;
  int num_valid = 0;
  for (int i = 0; i < n; ++i) {
    const uint8_t* row = img.ptr<uint8_t>(i);
    int64_t us = 0;
    uint16_t enc = 0;
    // Little-endian fields assembled byte by byte: independent of host order and alignment.
    for (int b = 7; b >= 0; --b)
      us = static_cast<int64_t>((static_cast<uint64_t>(us) << 8) | row[b]);
    enc = static_cast<uint16_t>(row[8] | (row[9] << 8));
    out->stamps[i] = static_cast<double>(us) * 1e-6;
    out->azimuths[i] = enc / kOxfordEncoderSize * 2.0 * M_PI;
    const bool ok = row[10] == 255 && enc < kOxfordEncoderSize && us > 0;
    out->valid[i] = ok ? 1 : 0;
    num_valid += ok ? 1 : 0;
  }
  if (num_valid == 0) return coral::fail(error, "Oxford radar image has no valid row (flag 255)");
  // Reference time = first valid azimuth (row 0 normally; equals the PNG name, the stamp GT and TF
  // refer to).
  int first = 0;
  while (!out->valid[first]) ++first;
  out->stamp = out->stamps[first];
  // Range bins share the buffer (no copy); clone if img may be modified later.
  out->power = img.colRange(kOxfordMeta, kOxfordCols);
  return checkSweep(*out, PolarImageConfig::oxfordCts350x().scan_period, error);
}

bool loadOxfordScan(const std::string& png_path, PolarScan* out, std::string* error) {
  cv::Mat img = cv::imread(png_path, cv::IMREAD_UNCHANGED);
  if (img.empty()) return coral::fail(error, "cannot read radar image '" + png_path + "'");
  std::string e;
  if (!decodeOxfordImage(img, out, &e)) return coral::fail(error, png_path + ": " + e);
  return true;
}

bool decodePolarImage(const cv::Mat& mono8, const PolarImageConfig& cfg, double stamp,
                      PolarScan* out, std::string* error) {
  if (out == nullptr) return coral::fail(error, "decodePolarImage: null output");
  const std::string bad = cfg.validate();
  if (!bad.empty()) return coral::fail(error, "invalid polar image config: " + bad);
  if (mono8.empty()) return coral::fail(error, "polar image is empty");
  if (mono8.type() != CV_8UC1)
    return coral::fail(error,
                       "polar image must be 8-bit single channel (mono8), got " + typeName(mono8));
  if (cfg.num_azimuths > 0 && mono8.rows != cfg.num_azimuths)
    return coral::fail(error, "polar image has " + std::to_string(mono8.rows) + " rows, expected " +
                                  std::to_string(cfg.num_azimuths) + " azimuths");
  if (mono8.cols <= cfg.first_data_column)
    return coral::fail(error, "polar image has " + std::to_string(mono8.cols) +
                                  " columns, not more than first_data_column = " +
                                  std::to_string(cfg.first_data_column));
  if (!std::isfinite(stamp)) return coral::fail(error, "polar image stamp is not finite");
  const int n = mono8.rows;
  const double sign = cfg.direction == AzimuthDirection::kCounterClockwise ? 1.0 : -1.0;
  out->azimuths.resize(n);
  out->stamps.resize(n);
  out->valid.assign(n, 1);
  for (int i = 0; i < n; ++i) {
    // Eq. 8: theta = 2 pi a / N_a, rotated by the mounting offset and mirrored for cw.
    double a = cfg.azimuth_offset_rad + sign * 2.0 * M_PI * i / n;
    a = std::remainder(a, 2.0 * M_PI);
    out->azimuths[i] = a;
    out->stamps[i] = stamp + cfg.scan_period * i / n;
  }
  out->power = mono8.colRange(cfg.first_data_column, mono8.cols);
  out->range_resolution = cfg.range_resolution;
  out->stamp = stamp;
  return true;
}

}  // namespace radar
}  // namespace coral_introspection
