// k-strongest masking and Radar Intensity Peak (RIP) features (paper Sec. III-E, Alg. 1).
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/coral/types.hpp"
#include "coral_introspection/radar/polar_scan.hpp"

namespace coral_introspection {
namespace radar {

// Defaults from Sec. V-A (CorAl-Radar).
struct RipConfig {
  int k = 12;                    // k-strongest bins kept per azimuth (Alg. 1 line 3)
  double z_min = 70;             // noise floor [intensity 0-255], bins and region strength
  int window = 2;                // w: region strength = mean over 2w+1 bins (Alg. 1 line 6)
  double min_range = 2.5;        // [m] closer bins are ignored (vehicle / sensor mount)
  double max_range = 1000.0;     // [m] farther bins are ignored
  std::string validate() const;  // empty when valid
};

struct RadarFeatures {
  coral::Points points;          // sensor frame, z = 0 (Eq. 8)
  std::vector<float> intensity;  // region strength S[r] of the peak (mean of 2w+1 bins)
  std::vector<double> stamps;    // [s] time of the point's azimuth
};

// Indices (ascending) of the k largest bins of row[first_bin, end_bin) that are >= z_min;
// all qualifying bins when fewer than k. Ties at the k-th value: lower bins win.
void kStrongest(const uint8_t* row, int first_bin, int end_bin, int k, double z_min,
                std::vector<int>* bins);
// Same, reusing *scratch between calls (no allocation per row in the hot loop).
void kStrongest(const uint8_t* row, int first_bin, int end_bin, int k, double z_min,
                std::vector<uint32_t>* scratch, std::vector<int>* bins);

// Alg. 1 over every valid row of scan. Returns false with *error on an invalid config or
// malformed scan (sizes disagree, not CV_8UC1); never throws.
bool extractRipFeatures(const PolarScan& scan, const RipConfig& cfg, RadarFeatures* out,
                        std::string* error);

}  // namespace radar
}  // namespace coral_introspection
