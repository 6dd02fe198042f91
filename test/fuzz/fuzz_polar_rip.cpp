// libFuzzer harness: polar radar images -> decoder -> RIP features (Alg. 1).
// Byte 0 picks the layout. Oxford: a valid 400 x 3779 sweep whose row metadata (stamp,
// encoder, flag) is XOR-ed with input bytes (zeros keep it valid, so both the sweep check
// and RIP are reached) and whose range bins are filled from the input. Plain: an image of
// fuzzed size, first data column, direction, period and stamp. Both go through RIP with a
// fuzzed config; whatever is accepted must give finite features that satisfy Alg. 1.
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>

#include "coral_introspection/radar/polar_scan.hpp"
#include "coral_introspection/radar/rip_features.hpp"
#include "fuzz_input.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::radar;
using coral_fuzz::FuzzInput;

namespace {

// An Oxford execution scans 400 rows; with the sanitizers and the fuzzer's comparison
// tracing every bin scanned costs, so the written window and the RIP range stay short
// (about 1 ms per execution instead of 6 ms with 256 bins up to 30 m). RIP's code paths do
// not depend on how far the range reaches.
constexpr int kBinWindow = 64;  // bins written per row
constexpr int kMaxShift = 16;   // per-row offset of that window

// The synthetic Oxford sweep of test_polar_scan.cpp: row i at t0 + 625 i us, encoder 14 i + 13.
cv::Mat oxfordSweep() {
  cv::Mat img(400, 3779, CV_8UC1, cv::Scalar(0));
  for (int i = 0; i < 400; ++i) {
    uint8_t* row = img.ptr<uint8_t>(i);
    const int64_t us = 1547131046353776 + 625 * i;
    for (int b = 0; b < 8; ++b) row[b] = static_cast<uint8_t>((us >> (8 * b)) & 0xFF);
    const int enc = 14 * i + 13;
    row[8] = enc & 0xFF;
    row[9] = (enc >> 8) & 0xFF;
    row[10] = 255;
  }
  return img;
}

// Copies the rest of the input into a window of the data columns of every row, cyclically,
// the window shifted per row (at most kMaxShift + kBinWindow columns from first_col).
void fillBins(FuzzInput& in, cv::Mat& img, int first_col) {
  const std::size_t n = in.remaining();
  if (n == 0) return;
  const uint8_t* src = in.rest();
  const int step = 1 + src[0] % 61;
  const int width = std::min(img.cols - first_col, kBinWindow);
  const int shifts = std::min(img.cols - first_col - width, kMaxShift) + 1;
  for (int r = 0; r < img.rows; ++r) {
    uint8_t* row = img.ptr<uint8_t>(r) + first_col + (r * 37) % shifts;
    for (int c = 0; c < width; ++c) row[c] = src[(static_cast<std::size_t>(r) * step + c) % n];
  }
}

RipConfig ripConfig(FuzzInput& in) {
  RipConfig c;
  c.k = in.range(1, 40);
  c.z_min = in.byte() + in.range(0, 3) * 0.25;  // fractional floors too
  c.window = in.range(0, 6);
  c.min_range = in.range(0, 20) * 0.125;
  // Up to 7.5 m: past the written bins (3.5 m) Oxford rows are zeros, and scanning them
  // finds nothing.
  c.max_range = c.min_range + in.range(-1, 40) * 0.125;  // may be invalid (<= min_range)
  return c;
}

void checkFeatures(const PolarScan& scan, const RipConfig& cfg, const RadarFeatures& f) {
  CORAL_FUZZ_CHECK(f.points.size() == f.intensity.size() && f.points.size() == f.stamps.size());
  CORAL_FUZZ_CHECK(f.points.size() <= static_cast<std::size_t>(scan.power.rows) * cfg.k);
  const double max_r = scan.power.cols * scan.range_resolution;
  for (std::size_t i = 0; i < f.points.size(); ++i) {
    const Vec3& p = f.points[i];
    CORAL_FUZZ_CHECK(p.allFinite() && p.z() == 0.0);
    const double r = p.head<2>().norm();
    CORAL_FUZZ_CHECK(r >= cfg.min_range - 1e-6 && r <= std::min(cfg.max_range, max_r) + 1e-6);
    CORAL_FUZZ_CHECK(f.intensity[i] > cfg.z_min - 1e-4 && f.intensity[i] <= 255.f);  // line 9
    CORAL_FUZZ_CHECK(std::isfinite(f.stamps[i]));
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  FuzzInput in(data, size);
  const bool oxford = in.byte() & 1;
  PolarScan scan;
  std::string err;
  cv::Mat img;
  bool ok = false;
  if (oxford) {
    // One image reused across executions (a 1.5 MB clone would dominate the run time):
    // metadata and the written bins are reset from the pristine sweep first.
    static const cv::Mat base = oxfordSweep();
    static cv::Mat work = base.clone();
    base.colRange(0, 11 + kMaxShift + kBinWindow)
        .copyTo(work.colRange(0, 11 + kMaxShift + kBinWindow));
    img = work;
    // Row metadata: up to 64 rows (chosen by the input) get XOR-ed stamp/encoder/flag bytes.
    const int edits = in.range(0, 64);
    for (int e = 0; e < edits; ++e) {
      const int row = in.take<uint16_t>() % 400;
      for (int b = 0; b < 11; ++b) img.at<uint8_t>(row, b) ^= in.byte();
    }
    const RipConfig rip = ripConfig(in);
    fillBins(in, img, 11);
    ok = decodeOxfordImage(img, &scan, &err);
    CORAL_FUZZ_CHECK(ok || !err.empty());
    if (ok) {
      CORAL_FUZZ_CHECK(checkSweep(scan, 0.25, nullptr));
      RadarFeatures f;
      if (extractRipFeatures(scan, rip, &f, &err)) checkFeatures(scan, rip, f);
    }
    return 0;
  }
  PolarImageConfig cfg;
  cfg.range_resolution = in.range(-1, 200) * 0.005;  // may be invalid (<= 0)
  cfg.num_azimuths = in.range(0, 3) == 0 ? 0 : in.range(1, 64);
  const int rows = in.range(0, 3) == 0 ? in.range(1, 70) : cfg.num_azimuths;
  const int cols = in.range(1, 255) + in.range(0, 3) * 256;
  cfg.first_data_column = in.range(-1, 30);
  cfg.direction =
      in.byte() & 1 ? AzimuthDirection::kClockwise : AzimuthDirection::kCounterClockwise;
  cfg.azimuth_offset_rad = in.take<float>();    // any float, NaN and Inf included
  cfg.scan_period = in.range(-1, 40) * 0.0125;  // may be invalid (< 0)
  const double stamp =
      in.range(0, 7) == 0 ? std::numeric_limits<double>::quiet_NaN() : in.take<uint32_t>() * 1e-3;
  const RipConfig rip = ripConfig(in);
  img = cv::Mat(std::max(rows, 1), cols, CV_8UC1, cv::Scalar(0));
  fillBins(in, img, std::min(std::max(cfg.first_data_column, 0), cols - 1));
  ok = decodePolarImage(img, cfg, stamp, &scan, &err);
  CORAL_FUZZ_CHECK(ok || !err.empty());
  if (!ok) return 0;
  CORAL_FUZZ_CHECK(static_cast<int>(scan.azimuths.size()) == img.rows);
  for (double a : scan.azimuths) CORAL_FUZZ_CHECK(std::isfinite(a));
  RadarFeatures f;
  if (extractRipFeatures(scan, rip, &f, &err)) checkFeatures(scan, rip, f);
  return 0;
}
