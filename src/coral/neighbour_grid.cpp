#include "coral_introspection/coral/neighbour_grid.hpp"

#include <algorithm>
#include <numeric>

namespace coral_introspection {
namespace core {

NeighbourGrid::NeighbourGrid(const Points& a, const Points& b, double cell_size, int dim)
    : dim_(dim), inv_cell_(1.0 / cell_size) {
  const std::size_t na = a.size(), n = a.size() + b.size();
  auto at = [&](std::size_t i) -> const Vec3& { return i < na ? a[i] : b[i - na]; };
  // Sorting by (cell key, original index) makes each cell's points contiguous (cache
  // friendly) with a's points before b's.
  std::vector<std::pair<uint64_t, uint32_t>> keyed(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p = at(i);
    keyed[i] = {key(cellCoord(p.x()), cellCoord(p.y()), dim == 3 ? cellCoord(p.z()) : 0),
                static_cast<uint32_t>(i)};
  }
  std::sort(keyed.begin(), keyed.end());
  points_.resize(n);
  index_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto i32 = static_cast<uint32_t>(i);
    points_[i] = at(keyed[i].second);
    index_[i] = keyed[i].second;
    if (i == 0 || keyed[i].first != keyed[i - 1].first) {
      const Vec3& p = points_[i];
      cells_.push_back({keyed[i].first, i32, i32, i32, cellCoord(p.x()), cellCoord(p.y()),
                        dim == 3 ? cellCoord(p.z()) : 0});
    }
    Cell& c = cells_.back();
    c.end = i32 + 1;
    if (keyed[i].second < na) c.mid = i32 + 1;
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

void NeighbourGrid::neighbourRanges(std::size_t c, int reach, std::vector<Range>* out) const {
  out->clear();
  const Cell& cell = cells_[c];
  const int zr = dim_ == 3 ? reach : 0;
  for (int64_t ix = cell.x - reach; ix <= cell.x + reach; ++ix)
    for (int64_t iy = cell.y - reach; iy <= cell.y + reach; ++iy)
      for (int64_t iz = cell.z - zr; iz <= cell.z + zr; ++iz)
        if (const Cell* n = find(key(ix, iy, iz))) out->push_back(range(*n));
}

}  // namespace core
}  // namespace coral_introspection
