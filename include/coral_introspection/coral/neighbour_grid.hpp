// Uniform hash grid for fixed-radius neighbour queries. For CorAl's radius searches on a
// few thousand points this is cheaper than a kd-tree: a query visits 3^N cells found by
// one hash probe each, and points of a cell are contiguous in memory.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace core {

class NeighbourGrid {
 public:
  // cell_size > 0 [m]; dim 2 ignores z. Non-finite points must be removed beforehand.
  NeighbourGrid(const Points& points, double cell_size, int dim)
      : NeighbourGrid(points, Points(), cell_size, dim) {}
  // One grid over two clouds: within every cell the points of `a` come first, then those of
  // `b`, so one cell lookup serves queries against both (CorAl's own and other clouds).
  // Original indices: i for a[i], a.size() + i for b[i].
  NeighbourGrid(const Points& a, const Points& b, double cell_size, int dim);

  // Calls f(point, original_index) for every point with |point - q| <= radius.
  template <class F>
  void forEachWithin(const Vec3& q, double radius, F&& f) const {
    if (points_.empty()) return;
    const double r2 = radius * radius;
    const int reach = static_cast<int>(std::ceil(radius * inv_cell_));
    const int64_t cx = cellCoord(q.x()), cy = cellCoord(q.y());
    const int64_t cz = dim_ == 3 ? cellCoord(q.z()) : 0;
    const int zr = dim_ == 3 ? reach : 0;
    for (int64_t ix = cx - reach; ix <= cx + reach; ++ix)
      for (int64_t iy = cy - reach; iy <= cy + reach; ++iy)
        for (int64_t iz = cz - zr; iz <= cz + zr; ++iz) {
          const Cell* c = find(key(ix, iy, iz));
          if (c == nullptr) continue;
          for (uint32_t i = c->begin; i < c->end; ++i) {
            const Vec3& p = points_[i];
            const double dx = p.x() - q.x(), dy = p.y() - q.y();
            const double dz = dim_ == 3 ? p.z() - q.z() : 0.0;
            if (dx * dx + dy * dy + dz * dz <= r2) f(p, index_[i]);
          }
        }
  }

  std::size_t size() const { return points_.size(); }

  // Cell-batched access for queries of every point of a grid (CorAl): the neighbour cells
  // are looked up once per cell instead of once per point.
  struct Range {
    const Vec3* begin;
    const Vec3* mid;  // [begin, mid): points of cloud a, [mid, end): points of cloud b
    const Vec3* end;
  };
  std::size_t numCells() const { return cells_.size(); }
  // Points of cell c (contiguous) and their original indices.
  Range cellPoints(std::size_t c) const { return range(cells_[c]); }
  const uint32_t* cellIndices(std::size_t c) const { return index_.data() + cells_[c].begin; }
  // Non-empty cells within `reach` cells of cell c (including c itself).
  void neighbourRanges(std::size_t c, int reach, std::vector<Range>* out) const;

 private:
  struct Cell {
    uint64_t key;
    uint32_t begin, mid, end;
    int64_t x, y, z;  // integer cell coordinates
  };
  Range range(const Cell& c) const {
    return {points_.data() + c.begin, points_.data() + c.mid, points_.data() + c.end};
  }
  int64_t cellCoord(double v) const { return static_cast<int64_t>(std::floor(v * inv_cell_)); }
  static uint64_t key(int64_t x, int64_t y, int64_t z) {
    // 21 bits per axis; cells that wrap onto one key merely share a bucket (distance is
    // always checked), so correctness never depends on the packing.
    constexpr uint64_t m = (1u << 21) - 1;
    return (static_cast<uint64_t>(x) & m) | ((static_cast<uint64_t>(y) & m) << 21) |
           ((static_cast<uint64_t>(z) & m) << 42);
  }
  static uint64_t hash(uint64_t k) { return (k * 0x9E3779B97F4A7C15ull) >> 20; }
  const Cell* find(uint64_t k) const {
    for (uint64_t s = hash(k) & mask_;; s = (s + 1) & mask_) {
      const int32_t ci = table_[s];
      if (ci < 0) return nullptr;
      if (cells_[ci].key == k) return &cells_[ci];
    }
  }

  int dim_;
  double inv_cell_;
  Points points_;                // sorted by cell
  std::vector<uint32_t> index_;  // original index of points_[i]
  std::vector<Cell> cells_;
  std::vector<int32_t> table_;  // open addressing, -1 = empty
  uint64_t mask_ = 0;
};

}  // namespace core
}  // namespace coral_introspection
