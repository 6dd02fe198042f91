// Uniform hash grid for fixed-radius neighbour queries. For CorAl's radius searches this is
// cheaper than a kd-tree: a query visits only the cells that intersect its ball (one hash
// probe each), and the points of a cell are contiguous in memory.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace coral {

class NeighbourGrid {
 public:
  // cell_size > 0 [m]; dim 2 ignores z. Points must be finite. Coordinates beyond
  // kMaxCell cells from the origin share the outermost cell layer: queries stay exact
  // (every distance is checked), only slower there.
  NeighbourGrid(const Points& points, double cell_size, int dim)
      : NeighbourGrid(points, Points(), cell_size, dim) {}
  // One grid over two clouds: within every cell the points of `a` come first, then those of
  // `b`, so one cell lookup serves queries against both (CorAl's own and other clouds).
  // Original indices: i for a[i], a.size() + i for b[i]. Cells are numbered in the order
  // their first point appears in a then b (deterministic).
  NeighbourGrid(const Points& a, const Points& b, double cell_size, int dim);

  struct Range {
    const Vec3* begin;
    const Vec3* mid;  // [begin, mid): points of cloud a, [mid, end): points of cloud b
    const Vec3* end;
  };
  // Positions [begin, end) in sortedPoints() (and in coordinates()).
  struct Span {
    uint32_t begin, end;
  };

  // Calls f(range) for every non-empty cell that intersects the ball of `radius` around q
  // (cells whose box lies farther than radius are skipped, so the work follows the radius,
  // not the cell size).
  template <class F>
  void forEachCellNear(const Vec3& q, double radius, F&& f) const {
    if (points_.empty()) return;
    // A point exactly at `radius` (a tie, common on quantised coordinates: q.x = -0.1,
    // p.x = -0.35, r = 0.25 m) passes the callers' rounded test |p - q|^2 <= r^2 even when
    // q.x - r rounds into the next cell. Each axis's cell range, and the pruning, use a reach
    // wider by far more than rounding error (kTieMargin relative to radius + |coordinate|;
    // under 0.11 cell up to where coordinates are clamped), so every point a distance test
    // can accept lies in a visited cell.
    auto reach = [&](double v) { return radius + kTieMargin * (radius + std::abs(v)); };
    const double rx = reach(q.x()), ry = reach(q.y()), rz = dim_ == 3 ? reach(q.z()) : 0.0;
    const double r_max = std::max({rx, ry, rz});
    const double r2 = r_max * r_max;
    const int64_t x0 = cellCoord(q.x() - rx), x1 = cellCoord(q.x() + rx);
    const int64_t y0 = cellCoord(q.y() - ry), y1 = cellCoord(q.y() + ry);
    const int64_t z0 = dim_ == 3 ? cellCoord(q.z() - rz) : 0;
    const int64_t z1 = dim_ == 3 ? cellCoord(q.z() + rz) : 0;
    // Keys of the block's cells follow from its first corner's when both corners pack.
    uint64_t k0 = 0, k1 = 0;
    const bool packed = pack(x0, y0, z0, &k0) && pack(x1, y1, z1, &k1);
    for (int64_t ix = x0; ix <= x1; ++ix) {
      const double gx = gap(q.x(), ix);
      if (gx > r2) continue;
      for (int64_t iy = y0; iy <= y1; ++iy) {
        const double gxy = gx + gap(q.y(), iy);
        if (gxy > r2) continue;
        const uint64_t kxy =
            k0 + static_cast<uint64_t>(ix - x0) + (static_cast<uint64_t>(iy - y0) << kPackBits);
        for (int64_t iz = z0; iz <= z1; ++iz) {
          if (dim_ == 3 && gxy + gap(q.z(), iz) > r2) continue;
          const Bounds* c =
              packed ? findNear(kxy + (static_cast<uint64_t>(iz - z0) << (2 * kPackBits)))
                     : find(ix, iy, iz);
          if (c != nullptr) f(range(*c));
        }
      }
    }
  }

  // Calls f(point, original_index) for every point with |point - q| <= radius.
  template <class F>
  void forEachWithin(const Vec3& q, double radius, F&& f) const {
    const double r2 = radius * radius;
    forEachCellNear(q, radius, [&](const Range& rg) {
      for (const Vec3* p = rg.begin; p != rg.end; ++p) {
        const double dx = p->x() - q.x(), dy = p->y() - q.y();
        const double dz = dim_ == 3 ? p->z() - q.z() : 0.0;
        if (dx * dx + dy * dy + dz * dz <= r2) f(*p, index_[p - points_.data()]);
      }
    });
  }

  std::size_t size() const { return points_.size(); }
  double cellSize() const { return cell_; }
  // Points sorted by cell, their original indices, and the position of a point in them.
  const Points& sortedPoints() const { return points_; }
  const std::vector<uint32_t>& sortedIndices() const { return index_; }
  uint32_t position(const Vec3* p) const { return static_cast<uint32_t>(p - points_.data()); }
  // The sorted points' coordinates along axis 0, 1, 2 (2D grids: 0, 1 only) as one array
  // each (structure of arrays): CorAl's moment kernel (src/coral/moments_kernel) loads four
  // points of a cell with one instruction per axis.
  const double* coordinates(int axis) const { return soa_[axis].get(); }

  // Cell-batched access for queries of every point of a grid (CorAl): the neighbour cells
  // are looked up once per cell instead of once per point.
  std::size_t numCells() const { return cells_.size(); }
  // Points of cell c (contiguous) and their original indices.
  Range cellPoints(std::size_t c) const { return range(cells_[c].b); }
  const uint32_t* cellIndices(std::size_t c) const { return index_.data() + cells_[c].b.begin; }
  // Cloud a's and cloud b's points of the 3 x 3 (x 3) cells around cell c (c included):
  // one span per cell that holds some, in a[0, *na) and b[0, *nb).
  static constexpr int kBlockCells = 27;
  void neighbourSpans(std::size_t c, Span* a, int* na, Span* b, int* nb) const;

  // Cell coordinates are clamped to +-kMaxCell: no float-to-integer overflow, no signed
  // overflow in neighbour arithmetic, whatever the input.
  static constexpr int64_t kMaxCell = int64_t{1} << 40;
  // Relative widening of a query's ball for the cell search (forEachCellNear).
  static constexpr double kTieMargin = 1e-13;

 private:
  struct Bounds {
    uint32_t begin, mid, end;  // points_[begin, mid): cloud a, [mid, end): cloud b
  };
  struct Cell {
    int64_t x, y, z;  // integer cell coordinates (the cell's identity)
    Bounds b;
    uint32_t slot;  // in near_ (cells that pack)
  };
  // A cell within 2^20 cells of the base cell on every axis (any real scan: the table
  // below holds its key and bounds, so a lookup reads one slot, not a slot then a Cell).
  // key 0 = empty (a packed key has bit 63 set).
  struct Slot {
    uint64_t key;   // kPacked | offsets from the base cell, 21 bits per axis
    uint32_t cell;  // index in cells_
    Bounds b;
  };
  static constexpr int kPackBits = 21;
  static constexpr int64_t kPackHalf = int64_t{1} << (kPackBits - 1);
  static constexpr uint64_t kPacked = uint64_t{1} << 63;

  Range range(const Bounds& b) const {
    return {points_.data() + b.begin, points_.data() + b.mid, points_.data() + b.end};
  }
  int64_t cellCoord(double v) const {
    // floor() of the clamped value without a libm call (NaN never reaches here).
    const double s =
        std::clamp(v * inv_cell_, -static_cast<double>(kMaxCell), static_cast<double>(kMaxCell));
    const auto t = static_cast<int64_t>(s);
    return t - (s < static_cast<double>(t) ? 1 : 0);
  }
  // Squared distance along one axis from v to cell i's interval (0 inside). The clamped
  // outer layer extends to infinity, so it is never skipped.
  double gap(double v, int64_t i) const {
    if (i <= -kMaxCell || i >= kMaxCell) return 0.0;
    const double lo = static_cast<double>(i) * cell_;
    const double d = std::max({0.0, lo - v, v - (lo + cell_)});
    return d * d;
  }
  // The packed key of a cell near the base cell; false when it is farther on some axis.
  bool pack(int64_t x, int64_t y, int64_t z, uint64_t* key) const {
    const auto ux = static_cast<uint64_t>(x - base_[0] + kPackHalf);
    const auto uy = static_cast<uint64_t>(y - base_[1] + kPackHalf);
    const auto uz = static_cast<uint64_t>(z - base_[2] + kPackHalf);
    if ((ux | uy | uz) >> kPackBits) return false;  // some offset outside [0, 2^21)
    *key = kPacked | ux | (uy << kPackBits) | (uz << (2 * kPackBits));
    return true;
  }
  std::size_t slotOf(uint64_t key) const { return (key * 0x9E3779B97F4A7C15ull) >> shift_; }
  static uint64_t hash(int64_t x, int64_t y, int64_t z) {
    uint64_t h = static_cast<uint64_t>(x) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<uint64_t>(y) * 0xC2B2AE3D27D4EB4Full;
    h ^= static_cast<uint64_t>(z) * 0x165667B19E3779F9ull;
    return h ^ (h >> 29);
  }
  const Bounds* findNear(uint64_t key) const {
    for (std::size_t s = slotOf(key);; s = (s + 1) & near_mask_) {
      const Slot& e = near_[s];
      if (e.key == key) return &e.b;
      if (e.key == 0) return nullptr;
    }
  }
  const Bounds* find(int64_t x, int64_t y, int64_t z) const {
    uint64_t key;
    if (pack(x, y, z, &key)) return findNear(key);
    if (far_.empty()) return nullptr;
    for (uint64_t s = hash(x, y, z) & far_mask_;; s = (s + 1) & far_mask_) {
      const int32_t ci = far_[s];
      if (ci < 0) return nullptr;
      const Cell& c = cells_[ci];
      if (c.x == x && c.y == y && c.z == z) return &c.b;
    }
  }
  // Adds the cell (x, y, z) unless present; its index in cells_.
  uint32_t insert(int64_t x, int64_t y, int64_t z) {
    uint64_t key;
    if (!pack(x, y, z, &key)) return insertFar(x, y, z);
    if (2 * (near_used_ + 1) > near_.size()) rebuildTables(2 * near_.size(), far_.size());
    std::size_t s = slotOf(key);
    while (near_[s].key != key && near_[s].key != 0) s = (s + 1) & near_mask_;
    if (near_[s].key == 0) {
      near_[s].key = key;
      near_[s].cell = static_cast<uint32_t>(cells_.size());
      cells_.push_back({x, y, z, {0, 0, 0}, static_cast<uint32_t>(s)});
      ++near_used_;
    }
    return near_[s].cell;
  }
  uint32_t insertFar(int64_t x, int64_t y, int64_t z);
  // Tables of near_slots and far_slots slots (powers of two; 0 = no far table), filled
  // from cells_.
  void rebuildTables(std::size_t near_slots, std::size_t far_slots);

  int dim_;
  double cell_, inv_cell_;
  Points points_;                     // sorted by cell
  std::unique_ptr<double[]> soa_[3];  // points_ by axis (allocated, not zeroed, then filled)
  std::vector<uint32_t> index_;       // original index of points_[i]
  std::vector<Cell> cells_;
  int64_t base_[3] = {0, 0, 0};  // the first point's cell
  std::vector<Slot> near_;       // open addressing by packed key
  std::size_t near_mask_ = 0;
  std::size_t near_used_ = 0;
  int shift_ = 64;            // slotOf: the top log2(near_.size()) bits of the product
  std::vector<int32_t> far_;  // cells not packable: open addressing, -1 = empty
  uint64_t far_mask_ = 0;
  std::size_t far_used_ = 0;
};

}  // namespace coral
}  // namespace coral_introspection
