#include "coral_introspection/coral/point_filter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace coral_introspection {
namespace coral {

namespace {

struct Cell {
  int64_t x, y, z;
  bool operator==(const Cell& o) const { return x == o.x && y == o.y && z == o.z; }
};

uint64_t hashCell(const Cell& c) {
  uint64_t h = static_cast<uint64_t>(c.x) * 0x9E3779B97F4A7C15ull;
  h ^= static_cast<uint64_t>(c.y) * 0xC2B2AE3D27D4EB4Full;
  h ^= static_cast<uint64_t>(c.z) * 0x165667B19E3779F9ull;
  return h ^ (h >> 29);
}

// The input itself when keep(p) holds for every point, otherwise the kept points in
// *storage (order kept); drop(p) is called for each point left out.
template <class Keep, class Drop>
const Points& keptPoints(const Points& in, Keep keep, Drop drop, Points* storage) {
  if (std::all_of(in.begin(), in.end(), keep)) return in;
  storage->clear();
  storage->reserve(in.size());
  for (const Vec3& p : in) {
    if (keep(p))
      storage->push_back(p);
    else
      drop(p);
  }
  return *storage;
}

// Removes the points for which keep(p) is false, and their covariances when there is one per
// point, order kept; drop(p) is called for each.
template <class Keep, class Drop>
void keepInScan(Scan& scan, Keep keep, Drop drop) {
  const bool with_cov = scan.covariances.size() == scan.points.size();
  std::size_t kept = 0;
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    if (!keep(scan.points[i])) {
      drop(scan.points[i]);
      continue;
    }
    scan.points[kept] = scan.points[i];
    if (with_cov) scan.covariances[kept] = scan.covariances[i];
    ++kept;
  }
  scan.points.resize(kept);
  if (with_cov) scan.covariances.resize(kept);
}

}  // namespace

const Points& usablePoints(const Points& in, double max_abs, Points* storage,
                           std::size_t* non_finite, std::size_t* out_of_range) {
  *non_finite = *out_of_range = 0;
  // |v| <= max_abs is false for NaN, so one test per coordinate finds both kinds.
  return keptPoints(
      in, [max_abs](const Vec3& p) { return isUsablePoint(p, max_abs); },
      [&](const Vec3& p) { ++*(p.allFinite() ? out_of_range : non_finite); }, storage);
}

void removeUnusable(Scan& scan, double max_abs, std::size_t* non_finite,
                    std::size_t* out_of_range) {
  keepInScan(
      scan, [max_abs](const Vec3& p) { return isUsablePoint(p, max_abs); },
      [&](const Vec3& p) { ++*(p.allFinite() ? out_of_range : non_finite); });
}

const Points& pointsWithinRange(const Points& in, const Vec3& origin, double max_range, int dim,
                                Points* storage, std::size_t* dropped) {
  *dropped = 0;
  return keptPoints(
      in, [&](const Vec3& p) { return withinRange(p, origin, max_range, dim); },
      [dropped](const Vec3&) { ++*dropped; }, storage);
}

void removeBeyondRange(Scan& scan, double max_range, int dim, std::size_t* dropped) {
  const Vec3 origin = scan.origin;
  keepInScan(
      scan, [&](const Vec3& p) { return withinRange(p, origin, max_range, dim); },
      [dropped](const Vec3&) { ++*dropped; });
}

Points strideSubsample(const Points& in, std::size_t max_points) {
  if (in.size() <= max_points) return in;
  Points out;
  out.reserve(max_points);
  for (std::size_t k = 0; k < max_points; ++k)
    out.push_back(in[static_cast<std::size_t>(static_cast<double>(k) * in.size() / max_points)]);
  return out;
}

std::size_t mergeCoincident(const Points& in, double tolerance, int dim, Points* out) {
  *out = in;
  if (!(tolerance > 0.0) || in.size() < 2) return 0;
  const double inv = 1.0 / tolerance;
  constexpr double kRange = 4e18;  // |index| below 2^62: no integer overflow
  std::size_t cap = 64;
  while (cap < 2 * in.size()) cap <<= 1;
  std::vector<int32_t> table(cap, -1);  // -> index in `out` of the group's first point
  std::vector<Cell> cells;
  std::vector<Vec3> offset_sum;  // per output point: sum of (p - first) of merged points
  std::vector<uint32_t> count;
  cells.reserve(in.size());
  out->clear();
  std::size_t merged = 0;
  for (const Vec3& p : in) {
    const double sx = std::floor(p.x() * inv), sy = std::floor(p.y() * inv);
    const double sz = dim == 3 ? std::floor(p.z() * inv) : 0.0;
    if (!(std::abs(sx) < kRange && std::abs(sy) < kRange && std::abs(sz) < kRange)) {
      out->push_back(p);  // cannot be keyed: kept as it is
      cells.push_back({INT64_MIN, INT64_MIN, static_cast<int64_t>(out->size())});
      offset_sum.push_back(Vec3::Zero());
      count.push_back(1);
      continue;
    }
    const Cell c{static_cast<int64_t>(sx), static_cast<int64_t>(sy), static_cast<int64_t>(sz)};
    uint64_t s = hashCell(c) & (cap - 1);
    while (table[s] >= 0 && !(cells[table[s]] == c)) s = (s + 1) & (cap - 1);
    if (table[s] < 0) {
      table[s] = static_cast<int32_t>(out->size());
      out->push_back(p);
      cells.push_back(c);
      offset_sum.push_back(Vec3::Zero());
      count.push_back(1);
    } else {
      const int32_t i = table[s];
      offset_sum[i] += p - (*out)[i];
      ++count[i];
      ++merged;
    }
  }
  for (std::size_t i = 0; i < out->size(); ++i)
    if (count[i] > 1) (*out)[i] += offset_sum[i] / static_cast<double>(count[i]);
  return merged;
}

}  // namespace coral
}  // namespace coral_introspection
