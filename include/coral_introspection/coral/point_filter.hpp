// Input hygiene before CorAl (issue 13): unusable points are named and counted, not scored.
//  - non-finite points and points beyond a sane coordinate range are dropped;
//  - a scan with more points than a bound is thinned (or refused by the caller), so the
//    work per pair is bounded;
//  - coincident points (duplicates, lidar no-returns at the origin) are merged into one, so
//    a cluster neither dominates its neighbours' covariances nor costs its square.
#pragma once

#include <cmath>

#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace coral {

// A point CorAl may use: every coordinate finite with |c| <= max_abs (false for NaN).
inline bool isUsablePoint(const Vec3& p, double max_abs) {
  return std::abs(p.x()) <= max_abs && std::abs(p.y()) <= max_abs && std::abs(p.z()) <= max_abs;
}

// The input itself when every point is finite with |x|, |y|, |z| <= max_abs (no copy),
// otherwise the usable points in *storage (order kept). Counts what was dropped.
const Points& usablePoints(const Points& in, double max_abs, Points* storage,
                           std::size_t* non_finite, std::size_t* out_of_range);

// Removes the points that are not usable (and their covariances, when there is one per
// point) from the scan, order kept. Counts what was dropped.
void removeUnusable(Scan& scan, double max_abs, std::size_t* non_finite, std::size_t* out_of_range);

// A point within max_range of origin (in x-y for dim 2); every point when max_range <= 0.
inline bool withinRange(const Vec3& p, const Vec3& origin, double max_range, int dim) {
  if (max_range <= 0.0) return true;
  const Vec3 d = p - origin;
  return (dim == 2 ? d.head<2>().squaredNorm() : d.squaredNorm()) <= max_range * max_range;
}

// The input itself when every point is within max_range of origin (CoralConfig::max_range:
// no-return readings written at the scanner's maximum range), otherwise those points in
// *storage (order kept). Counts what was dropped.
const Points& pointsWithinRange(const Points& in, const Vec3& origin, double max_range, int dim,
                                Points* storage, std::size_t* dropped);

// Removes the points beyond max_range of scan.origin (and their covariances, when there is one
// per point), order kept. Adds the number dropped to *dropped.
void removeBeyondRange(Scan& scan, double max_range, int dim, std::size_t* dropped);

// Every (n / max_points)-th point (a deterministic stride, order kept) so that exactly
// max_points remain; the input when it is not larger.
Points strideSubsample(const Points& in, std::size_t max_points);

// The whole-number stride that keeps at most max_points of n (every stride-th from the first):
// ceil(n / max_points), at least 1. For loops that visit a subset in place. max_points > 0.
inline std::size_t strideFor(std::size_t n, std::size_t max_points) {
  return n > max_points ? (n + max_points - 1) / max_points : 1;
}

// Points of one scan in the same cube of edge `tolerance` [m] (dim 2: square in x, y) are
// replaced by their centroid, kept at the place of the group's first point; a point alone
// is returned bit-identical, so input order and values survive when nothing coincides.
// tolerance <= 0 returns the input. Returns the number of points removed.
std::size_t mergeCoincident(const Points& in, double tolerance, int dim, Points* out);

}  // namespace coral
}  // namespace coral_introspection
