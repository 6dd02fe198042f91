// Building blocks of computeCoral (coral.cpp) shared with CoralPair (coral_pair.cpp), which
// evaluates one pair at many poses. Private to the coral library (not installed).
#pragma once

#include <vector>

#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/coral/neighbour_grid.hpp"

namespace coral_introspection {
namespace coral {
namespace detail {
// Internal linkage for the per-point helpers, as when they lived in coral.cpp: the compiler
// then inlines them into the scoring loops the same way. The neighbour kernel itself is in
// moments_kernel.hpp.
namespace {

template <int Dim>
double pointRadius(const CoralConfig& cfg, const Vec3& p, const Vec3& origin) {
  if (!cfg.dynamic_radius) return cfg.radius;  // no distance (square root) needed
  return dynamicRadius(cfg, (p - origin).template head<Dim>().norm());
}

inline void setPoint(PointEntropy& pe, const Vec3& p, bool in_a, double radius) {
  pe.position = p.cast<float>();
  pe.scan = in_a ? 0 : 1;
  pe.radius = static_cast<float>(radius);
}

}  // namespace

// The two scans after input hygiene (non-finite and out-of-range points dropped,
// max_points, coincident points merged) and the voxel filter. cloud[s] points at the input
// or at one of the buffers: not copyable.
struct PreparedClouds {
  const Points* cloud[2] = {nullptr, nullptr};
  Points storage[2], ranged[2], beamed[2], thinned[2], merged[2], voxels[2];
  PreparedClouds() = default;
  PreparedClouds(const PreparedClouds&) = delete;
  PreparedClouds& operator=(const PreparedClouds&) = delete;
};

// Fills *out and the input counts of *res (num_points_*, num_used_*, num_non_finite,
// num_out_of_range, num_beyond_max_range, num_beam_thinned, num_thinned, num_merged); max_range
// and the beam spacing (beam_step_deg, 2D) are measured from
// each scan's origin. False, with res->reason, when a scan is refused (refuse_over_max_points).
bool prepareClouds(const Scan& a, const Scan& b, const CoralConfig& cfg, PreparedClouds* out,
                   CoralResult* res);

// Stratified subset of at most cfg.max_queries points of each of the grid's two clouds
// (positions in grid.sortedPoints(), a's first); see coral.cpp.
std::vector<uint32_t> selectQueries(const NeighbourGrid& grid, const CoralConfig& cfg);

// Grid cell size for per-query searches (each query visits the cells its ball intersects).
double queryCellSize(const CoralConfig& cfg);

}  // namespace detail
}  // namespace coral
}  // namespace coral_introspection
