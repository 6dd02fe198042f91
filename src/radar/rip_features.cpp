#include "coral_introspection/radar/rip_features.hpp"

#include "coral_introspection/coral/validation.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace coral_introspection {
namespace radar {

namespace {

// Candidate keys order bins by strength: intensity in the high bits, then the bin index
// inverted so that on equal intensity the lower bin is "stronger". No indirection is
// needed to compare two candidates.
constexpr uint32_t kIndexBits = 20;
constexpr uint32_t kIndexMask = (1u << kIndexBits) - 1;
inline uint32_t makeKey(uint8_t v, int i) {
  return (static_cast<uint32_t>(v) << kIndexBits) | (kIndexMask - static_cast<uint32_t>(i));
}
inline int keyIndex(uint32_t key) { return static_cast<int>(kIndexMask - (key & kIndexMask)); }

// Writes the keys of the bins in [first, end) with Z >= t (t in 1..255). Radar rows are
// > 98 % below the noise floor, so this is the hot loop: 32 bytes are tested per branch
// with SSE2 and a block without any candidate costs about ten instructions.
// Returns the number of keys written to dst, which has room for end - first keys.
std::size_t binsAtLeast(const uint8_t* row, int first, int end, int t, uint32_t* const out) {
  uint32_t* dst = out;
  int i = first;
#if defined(__SSE2__)
  const __m128i tv = _mm_set1_epi8(static_cast<char>(t));
  for (; i + 32 <= end; i += 32) {
    const __m128i x0 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row + i));
    const __m128i x1 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row + i + 16));
    // x >= t  <=>  max(x, t) == x  (unsigned bytes); 32 bins tested per branch.
    const unsigned m0 =
        static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(_mm_max_epu8(x0, tv), x0)));
    const unsigned m1 =
        static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(_mm_max_epu8(x1, tv), x1)));
    for (uint32_t m = m0 | (m1 << 16); m; m &= m - 1) {
      const int b = i + __builtin_ctz(m);
      *dst++ = makeKey(row[b], b);
    }
  }
#endif
  for (; i < end; ++i)
    if (row[i] >= t) *dst++ = makeKey(row[i], i);
  return static_cast<std::size_t>(dst - out);
}

inline int binAt(const uint8_t* row, int cols, int n) {
  return n >= 0 && n < cols ? row[n] : 0;  // bins outside the row count as 0
}
}  // namespace

std::string RipConfig::validate() const {
  return coral::Problems()
      .require(k >= 1 && k <= 100000, "k", "in [1, 100000]", k)
      .require(z_min >= 0.0 && z_min <= 255.0, "z_min", "in [0, 255]", z_min)
      .require(window >= 0 && window <= 100, "window", "in [0, 100] bins", window)
      .require(min_range >= 0.0 && std::isfinite(min_range), "min_range", "finite and >= 0 m",
               min_range)
      .require(max_range > min_range, "max_range", "> min_range", max_range)
      .str();
}

void kStrongest(const uint8_t* row, int first_bin, int end_bin, int k, double z_min,
                std::vector<int>* bins) {
  std::vector<uint32_t> keys;
  kStrongest(row, first_bin, end_bin, k, z_min, &keys, bins);
}

void kStrongest(const uint8_t* row, int first_bin, int end_bin, int k, double z_min,
                std::vector<uint32_t>* keys, std::vector<int>* bins) {
  bins->clear();
  first_bin = std::max(0, first_bin);
  end_bin = std::min<int>(end_bin, kIndexMask);
  if (row == nullptr || k <= 0 || end_bin <= first_bin || !(z_min <= 255.0)) return;
  // The scratch only grows (never shrinks, never re-zeroed): room for every bin of the range.
  const std::size_t span = static_cast<std::size_t>(end_bin - first_bin);
  if (keys->size() < span) keys->resize(span);
  uint32_t* const key = keys->data();
  std::size_t n = 0;
  if (z_min <= 0.0) {
    for (int i = first_bin; i < end_bin; ++i) key[n++] = makeKey(row[i], i);
  } else {
    // Integer intensities: Z >= z_min  <=>  Z >= ceil(z_min), in 1..255.
    n = binsAtLeast(row, first_bin, end_bin, static_cast<int>(std::ceil(z_min)), key);
  }
  if (n > static_cast<std::size_t>(k)) {
    // The k largest by partial selection (O(n)), not a sorted insert per bin. Every bin
    // >= z_min competes, so a weak bin seen early is never dropped while fewer than k are
    // held (the reference implementation's bug).
    std::nth_element(key, key + (k - 1), key + n, std::greater<uint32_t>());
    n = static_cast<std::size_t>(k);
  }
  for (std::size_t j = 0; j < n; ++j) bins->push_back(keyIndex(key[j]));
  std::sort(bins->begin(), bins->end());
}

bool extractRipFeatures(const PolarScan& scan, const RipConfig& cfg, RadarFeatures* out,
                        std::string* error) {
  if (out == nullptr) return coral::fail(error, "extractRipFeatures: null output");
  out->points.clear();
  out->intensity.clear();
  out->stamps.clear();
  const std::string bad = cfg.validate();
  if (!bad.empty()) return coral::fail(error, "invalid RIP config: " + bad);
  if (scan.power.empty()) return coral::fail(error, "polar scan has no power data");
  if (scan.power.type() != CV_8UC1) return coral::fail(error, "polar scan power must be CV_8UC1");
  const int rows = scan.power.rows, cols = scan.power.cols;
  if (static_cast<int>(scan.azimuths.size()) != rows ||
      static_cast<int>(scan.stamps.size()) != rows || static_cast<int>(scan.valid.size()) != rows)
    return coral::fail(error, "polar scan: azimuths/stamps/valid sizes differ from " +
                                  std::to_string(rows) + " rows");
  if (!(scan.range_resolution > 0.0))
    return coral::fail(error, "polar scan: range_resolution must be > 0");
  const double res = scan.range_resolution;
  // Bins whose range r * res lies in [min_range, max_range] (clamped in double: no overflow).
  const int first = static_cast<int>(std::min<double>(cols, std::ceil(cfg.min_range / res - 1e-9)));
  const int end = static_cast<int>(std::min<double>(cols, std::floor(cfg.max_range / res) + 1));
  const int w = cfg.window;
  const double s_min = cfg.z_min * (2 * w + 1);  // S > z_min on sums (Alg. 1 line 9)

  std::vector<int> masked;
  std::vector<uint32_t> keys;
  masked.reserve(cols);
  keys.reserve(cols);
  std::vector<int> sums(2 * w + 1);
  const std::size_t expect = static_cast<std::size_t>(rows) * std::min(cfg.k, 64);
  out->points.reserve(expect);
  out->intensity.reserve(expect);
  out->stamps.reserve(expect);
  for (int a = 0; a < rows; ++a) {
    if (!scan.valid[a] || first >= end) continue;
    const uint8_t* z = scan.power.ptr<uint8_t>(a);
    kStrongest(z, first, end, cfg.k, cfg.z_min, &keys, &masked);  // Alg. 1 line 3
    if (masked.empty()) continue;
    const double c = std::cos(scan.azimuths[a]), s = std::sin(scan.azimuths[a]);
    int plateau_s = -1, plateau_end = 0;  // strength and last bin of the last kept peak
    for (const int r : masked) {
      // Scores of r and its 2w neighbours (Alg. 1 lines 5-6), kept as sums of 2w+1 bins.
      // sums[i] = sum of Z over [r - w + i - w, r - w + i + w], slid along by one bin.
      int acc = 0;
      if (r - 2 * w >= 0 && r + 2 * w < cols) {  // interior: no bounds checks
        for (int n = r - 2 * w; n <= r; ++n) acc += z[n];
        sums[0] = acc;
        for (int i = 1; i <= 2 * w; ++i) sums[i] = acc += z[r + i] - z[r - 2 * w + i - 1];
      } else {
        for (int n = r - 2 * w; n <= r; ++n) acc += binAt(z, cols, n);
        sums[0] = acc;
        for (int i = 1; i <= 2 * w; ++i)
          sums[i] = acc += binAt(z, cols, r + i) - binAt(z, cols, r - 2 * w + i - 1);
      }
      const int sr = sums[w];
      if (sr <= s_min) continue;  // line 9: region strength above the noise floor
      // Line 8: S[r] >= max over the 2w neighbours.
      bool peak = true;
      for (int j = 1; j <= w && peak; ++j) peak = sr >= sums[w - j] && sr >= sums[w + j];
      if (!peak) continue;
      // Equal strengths within w bins of the last kept peak are one plateau: keep its first
      // bin only (one feature per flat top instead of one per bin). Tracking the plateau's
      // last bin lets a long flat top of masked bins collapse into one feature.
      if (sr == plateau_s && r - plateau_end <= w) {
        plateau_end = r;
        continue;
      }
      plateau_s = sr;
      plateau_end = r;
      const double range = r * res;  // Eq. 8
      out->points.emplace_back(range * c, range * s, 0.0);
      out->intensity.push_back(static_cast<float>(sr) / (2 * w + 1));
      out->stamps.push_back(scan.stamps[a]);
    }
  }
  return true;
}

}  // namespace radar
}  // namespace coral_introspection
