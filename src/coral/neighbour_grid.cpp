#include "coral_introspection/coral/neighbour_grid.hpp"

#include <algorithm>

namespace coral_introspection {
namespace coral {

NeighbourGrid::NeighbourGrid(const Points& a, const Points& b, double cell_size, int dim)
    : dim_(dim), cell_(cell_size), inv_cell_(1.0 / cell_size) {
  const std::size_t na = a.size(), n = a.size() + b.size();
  auto at = [&](std::size_t i) -> const Vec3& { return i < na ? a[i] : b[i - na]; };
  auto cellOf = [&](const Vec3& p, int64_t* c) {
    c[0] = cellCoord(p.x());
    c[1] = cellCoord(p.y());
    c[2] = dim == 3 ? cellCoord(p.z()) : 0;
  };
  if (n > 0) cellOf(at(0), base_);
  // Half a slot per point: no growth for radar features (~5 points per cell) or voxelised
  // lidar (~4); doubled whenever it would become more than half full.
  rebuildTables(std::max<std::size_t>(16, n / 2), 0);
  cells_.reserve(n / 4 + 16);
  // Counting sort by cell, O(n): pass 1 gives every point its cell (cells numbered by first
  // appearance) and counts a's and b's points per cell; pass 2 scatters, keeping the input
  // order within a cell (a's points before b's).
  std::vector<uint32_t> cell_of(n);
  for (std::size_t i = 0; i < n; ++i) {
    int64_t c[3];
    cellOf(at(i), c);
    const uint32_t ci = insert(c[0], c[1], c[2]);
    cell_of[i] = ci;
    ++(i < na ? cells_[ci].b.mid : cells_[ci].b.end);  // counts of a (mid) and b (end) for now
  }
  uint32_t offset = 0;
  for (Cell& c : cells_) {
    const uint32_t count_a = c.b.mid, count_b = c.b.end;
    c.b = {offset, offset + count_a, offset + count_a + count_b};
    offset = c.b.end;
  }
  uint64_t key;
  for (const Cell& c : cells_)
    if (pack(c.x, c.y, c.z, &key)) near_[c.slot].b = c.b;
  points_.resize(n);
  index_.resize(n);
  std::vector<uint32_t> fill_a(cells_.size()), fill_b(cells_.size());
  for (std::size_t c = 0; c < cells_.size(); ++c) {
    fill_a[c] = cells_[c].b.begin;
    fill_b[c] = cells_[c].b.mid;
  }
  const int axes = dim == 3 ? 3 : 2;  // 2D: z is never read
  for (int axis = 0; axis < axes; ++axis) soa_[axis].reset(new double[n]);
  for (std::size_t i = 0; i < n; ++i) {
    const uint32_t dst = i < na ? fill_a[cell_of[i]]++ : fill_b[cell_of[i]]++;
    const Vec3& p = at(i);
    points_[dst] = p;
    index_[dst] = static_cast<uint32_t>(i);
    for (int axis = 0; axis < axes; ++axis) soa_[axis][dst] = p[axis];
  }
}

void NeighbourGrid::rebuildTables(std::size_t near_slots, std::size_t far_slots) {
  int bits = 0;
  while ((std::size_t{1} << bits) < near_slots) ++bits;
  near_.assign(std::size_t{1} << bits, Slot{0, 0, {0, 0, 0}});
  near_mask_ = near_.size() - 1;
  shift_ = 64 - bits;
  near_used_ = 0;
  far_.assign(far_slots, -1);
  far_mask_ = far_slots > 0 ? far_slots - 1 : 0;
  far_used_ = 0;
  for (std::size_t ci = 0; ci < cells_.size(); ++ci) {
    Cell& c = cells_[ci];
    uint64_t key;
    if (pack(c.x, c.y, c.z, &key)) {
      std::size_t s = slotOf(key);
      while (near_[s].key != 0) s = (s + 1) & near_mask_;
      near_[s] = {key, static_cast<uint32_t>(ci), c.b};
      c.slot = static_cast<uint32_t>(s);
      ++near_used_;
    } else {
      uint64_t s = hash(c.x, c.y, c.z) & far_mask_;
      while (far_[s] >= 0) s = (s + 1) & far_mask_;
      far_[s] = static_cast<int32_t>(ci);
      ++far_used_;
    }
  }
}

uint32_t NeighbourGrid::insertFar(int64_t x, int64_t y, int64_t z) {
  const auto fresh = static_cast<uint32_t>(cells_.size());
  if (!far_.empty()) {
    for (uint64_t s = hash(x, y, z) & far_mask_; far_[s] >= 0; s = (s + 1) & far_mask_) {
      const Cell& c = cells_[far_[s]];
      if (c.x == x && c.y == y && c.z == z) return static_cast<uint32_t>(far_[s]);
    }
  }
  // A new cell far from the base (adversarial or broken input only): the far table is
  // rebuilt, doubled, whenever it would become more than half full.
  cells_.push_back({x, y, z, {0, 0, 0}, 0});
  if (2 * (far_used_ + 1) > far_.size()) {
    rebuildTables(near_.size(), std::max<std::size_t>(16, 2 * far_.size()));
    return fresh;
  }
  ++far_used_;
  uint64_t s = hash(x, y, z) & far_mask_;
  while (far_[s] >= 0) s = (s + 1) & far_mask_;
  far_[s] = static_cast<int32_t>(fresh);
  return fresh;
}

void NeighbourGrid::neighbourSpans(std::size_t c, Span* a, int* na, Span* b, int* nb) const {
  *na = *nb = 0;
  auto add = [&](const Bounds* n) {
    if (n == nullptr) return;
    if (n->mid > n->begin) a[(*na)++] = {n->begin, n->mid};
    if (n->end > n->mid) b[(*nb)++] = {n->mid, n->end};
  };
  const Cell& cell = cells_[c];
  const int64_t rz = dim_ == 2 ? 0 : 1;
  uint64_t k0 = 0, k1 = 0;
  if (!pack(cell.x - 1, cell.y - 1, cell.z - rz, &k0) ||
      !pack(cell.x + 1, cell.y + 1, cell.z + rz, &k1)) {
    for (int64_t ix = cell.x - 1; ix <= cell.x + 1; ++ix)
      for (int64_t iy = cell.y - 1; iy <= cell.y + 1; ++iy)
        for (int64_t iz = cell.z - rz; iz <= cell.z + rz; ++iz) add(find(ix, iy, iz));
    return;
  }
  // Every cell of the block packs: its keys follow from the first corner's.
  constexpr uint64_t kY = uint64_t{1} << kPackBits, kZ = uint64_t{1} << (2 * kPackBits);
  if (dim_ == 2) {  // z is always 0: one loop less
    for (uint64_t dx = 0; dx < 3; ++dx)
      for (uint64_t dy = 0; dy < 3; ++dy) add(findNear(k0 + dx + dy * kY));
    return;
  }
  for (uint64_t dx = 0; dx < 3; ++dx)
    for (uint64_t dy = 0; dy < 3; ++dy)
      for (uint64_t dz = 0; dz < 3; ++dz) add(findNear(k0 + dx + dy * kY + dz * kZ));
}

}  // namespace coral
}  // namespace coral_introspection
