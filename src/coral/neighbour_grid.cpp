#include "coral_introspection/coral/neighbour_grid.hpp"

namespace coral_introspection {
namespace core {

NeighbourGrid::NeighbourGrid(const Points& a, const Points& b, double cell_size, int dim)
    : dim_(dim), cell_(cell_size), inv_cell_(1.0 / cell_size) {
  const std::size_t na = a.size(), n = a.size() + b.size();
  auto at = [&](std::size_t i) -> const Vec3& { return i < na ? a[i] : b[i - na]; };
  // Table at most half full so probes stay short (sized for the worst case, one cell per
  // point).
  std::size_t cap = 16;
  while (cap < 2 * n) cap <<= 1;
  mask_ = cap - 1;
  table_.assign(cap, -1);
  // Counting sort by cell, O(n): pass 1 gives every point its cell (cells numbered by first
  // appearance) and counts a's and b's points per cell; pass 2 scatters, keeping the input
  // order within a cell (a's points before b's).
  std::vector<uint32_t> cell_of(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p = at(i);
    const int64_t x = cellCoord(p.x()), y = cellCoord(p.y()), z = dim == 3 ? cellCoord(p.z()) : 0;
    uint64_t s = hash(x, y, z) & mask_;
    while (true) {
      const int32_t ci = table_[s];
      if (ci < 0) {
        table_[s] = static_cast<int32_t>(cells_.size());
        cells_.push_back({x, y, z, 0, 0, 0});
        break;
      }
      const Cell& c = cells_[ci];
      if (c.x == x && c.y == y && c.z == z) break;
      s = (s + 1) & mask_;
    }
    const auto ci = static_cast<uint32_t>(table_[s]);
    cell_of[i] = ci;
    ++(i < na ? cells_[ci].mid : cells_[ci].end);  // counts of a (mid) and b (end) for now
  }
  // Re-size the table to the cells (the worst case above is rarely needed): a table that
  // fits the cache keeps the queries' probes cheap.
  std::size_t tight = 16;
  while (tight < 2 * cells_.size()) tight <<= 1;
  if (tight < cap) {
    mask_ = tight - 1;
    table_.assign(tight, -1);
    for (std::size_t c = 0; c < cells_.size(); ++c) {
      uint64_t s = hash(cells_[c].x, cells_[c].y, cells_[c].z) & mask_;
      while (table_[s] >= 0) s = (s + 1) & mask_;
      table_[s] = static_cast<int32_t>(c);
    }
  }
  uint32_t offset = 0;
  for (Cell& c : cells_) {
    const uint32_t count_a = c.mid, count_b = c.end;
    c.begin = offset;
    c.mid = offset + count_a;
    c.end = c.mid + count_b;
    offset = c.end;
  }
  points_.resize(n);
  index_.resize(n);
  std::vector<uint32_t> fill_a(cells_.size()), fill_b(cells_.size());
  for (std::size_t c = 0; c < cells_.size(); ++c) {
    fill_a[c] = cells_[c].begin;
    fill_b[c] = cells_[c].mid;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const uint32_t dst = i < na ? fill_a[cell_of[i]]++ : fill_b[cell_of[i]]++;
    points_[dst] = at(i);
    index_[dst] = static_cast<uint32_t>(i);
  }
}

void NeighbourGrid::neighbourRanges(std::size_t c, int reach, std::vector<Range>* out) const {
  out->clear();
  const Cell& cell = cells_[c];
  if (dim_ == 2) {  // z is always 0: one loop less
    for (int64_t ix = cell.x - reach; ix <= cell.x + reach; ++ix)
      for (int64_t iy = cell.y - reach; iy <= cell.y + reach; ++iy)
        if (const Cell* n = find(ix, iy, 0)) out->push_back(range(*n));
    return;
  }
  for (int64_t ix = cell.x - reach; ix <= cell.x + reach; ++ix)
    for (int64_t iy = cell.y - reach; iy <= cell.y + reach; ++iy)
      for (int64_t iz = cell.z - reach; iz <= cell.z + reach; ++iz)
        if (const Cell* n = find(ix, iy, iz)) out->push_back(range(*n));
}

}  // namespace core
}  // namespace coral_introspection
