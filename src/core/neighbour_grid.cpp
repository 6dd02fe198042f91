#include "coral_introspection/core/neighbour_grid.hpp"

#include <algorithm>
#include <numeric>

namespace coral_introspection {
namespace core {

NeighbourGrid::NeighbourGrid(const Points& points, double cell_size, int dim)
    : dim_(dim), inv_cell_(1.0 / cell_size) {
  const std::size_t n = points.size();
  std::vector<std::pair<uint64_t, uint32_t>> keyed(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p = points[i];
    keyed[i] = {key(cellCoord(p.x()), cellCoord(p.y()), dim == 3 ? cellCoord(p.z()) : 0),
                static_cast<uint32_t>(i)};
  }
  std::sort(keyed.begin(), keyed.end());
  points_.resize(n);
  index_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    points_[i] = points[keyed[i].second];
    index_[i] = keyed[i].second;
    if (i == 0 || keyed[i].first != keyed[i - 1].first)
      cells_.push_back({keyed[i].first, static_cast<uint32_t>(i), static_cast<uint32_t>(i)});
    cells_.back().end = static_cast<uint32_t>(i + 1);
  }
  // Table at most half full so probes stay short.
  std::size_t cap = 16;
  while (cap < 2 * cells_.size()) cap <<= 1;
  mask_ = cap - 1;
  table_.assign(cap, -1);
  for (std::size_t c = 0; c < cells_.size(); ++c) {
    uint64_t s = hash(cells_[c].key) & mask_;
    while (table_[s] >= 0) s = (s + 1) & mask_;
    table_[s] = static_cast<int32_t>(c);
  }
}

}  // namespace core
}  // namespace coral_introspection
