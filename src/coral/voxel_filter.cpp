#include "coral_introspection/coral/voxel_filter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace coral_introspection {
namespace coral {

namespace {

constexpr int kBits = 21;  // per axis, 63 bits in one key
constexpr uint64_t kMask = (uint64_t{1} << kBits) - 1;
constexpr double kLimit = double(1 << (kBits - 1));  // |voxel index| < 2^20
constexpr uint64_t kEmpty = ~uint64_t{0};            // no valid key has bit 63 set

// One voxel, stored in the hash table itself (one random memory access per point). Sums
// are of offsets from the voxel's corner, so float keeps sub-micrometre precision anywhere.
struct Slot {
  uint64_t key = kEmpty;
  float sx = 0.f, sy = 0.f, sz = 0.f;
  uint32_t n = 0;
};

uint64_t mix(uint64_t k) {
  k *= 0x9E3779B97F4A7C15ull;
  return k ^ (k >> 31);
}

// Lower corner [m] of the voxel with biased index u along one axis.
double corner(uint64_t u, double leaf) {
  return (static_cast<double>(static_cast<int64_t>(u)) - kLimit) * leaf;
}

// Open addressing, doubled when half full.
class VoxelTable {
 public:
  explicit VoxelTable(std::size_t expected) {
    std::size_t cap = 1024;
    while (cap < 2 * expected) cap <<= 1;
    slots_.assign(cap, Slot());
  }
  Slot& at(uint64_t key) {
    Slot* s = &probe(slots_, key);
    if (s->key == kEmpty) {
      if (2 * (used_ + 1) > slots_.size()) {
        grow();
        s = &probe(slots_, key);
      }
      s->key = key;
      ++used_;
    }
    return *s;
  }
  const std::vector<Slot>& slots() const { return slots_; }
  std::size_t size() const { return used_; }

 private:
  static Slot& probe(std::vector<Slot>& t, uint64_t key) {
    const uint64_t mask = t.size() - 1;
    uint64_t i = mix(key) & mask;
    while (t[i].key != key && t[i].key != kEmpty) i = (i + 1) & mask;
    return t[i];
  }
  void grow() {
    std::vector<Slot> bigger(2 * slots_.size());
    for (const Slot& s : slots_)
      if (s.key != kEmpty) probe(bigger, s.key) = s;
    slots_.swap(bigger);
  }
  std::vector<Slot> slots_;
  std::size_t used_ = 0;
};

}  // namespace

Points voxelFilter(const Points& in, double leaf, int dim) {
  if (!(leaf > 0.0)) return in;
  const double inv = 1.0 / leaf;
  Points out;
  // Dense lidar clouds keep roughly one voxel in 8-16 points at useful leaves.
  VoxelTable table(in.size() / 16);
  // Voxel indices biased by 2^20 are non-negative, so truncation is floor() (no libm call)
  // and each fits its 21-bit field of the key as it is.
  for (const Vec3& p : in) {
    const double bx = p.x() * inv + kLimit, by = p.y() * inv + kLimit;
    const double bz = dim == 3 ? p.z() * inv + kLimit : kLimit;
    if (!(bx >= 0.0 && bx < 2 * kLimit && by >= 0.0 && by < 2 * kLimit && bz >= 0.0 &&
          bz < 2 * kLimit)) {
      out.push_back(p);  // outside the packable range: kept as it is
      continue;
    }
    // Signed conversions: unsigned ones cost a branch each without AVX-512.
    const auto ux = static_cast<uint64_t>(static_cast<int64_t>(bx));
    const auto uy = static_cast<uint64_t>(static_cast<int64_t>(by));
    const auto uz = static_cast<uint64_t>(static_cast<int64_t>(bz));
    Slot& s = table.at(ux | (uy << kBits) | (uz << (2 * kBits)));
    s.sx += static_cast<float>(p.x() - corner(ux, leaf));
    s.sy += static_cast<float>(p.y() - corner(uy, leaf));
    s.sz += static_cast<float>(dim == 3 ? p.z() - corner(uz, leaf) : p.z());
    ++s.n;
  }
  out.reserve(out.size() + table.size());
  for (const Slot& s : table.slots()) {
    if (s.key == kEmpty) continue;
    const double n = s.n;
    const double cz = dim == 3 ? corner((s.key >> (2 * kBits)) & kMask, leaf) : 0.0;
    out.emplace_back(corner(s.key & kMask, leaf) + s.sx / n,
                     corner((s.key >> kBits) & kMask, leaf) + s.sy / n, cz + s.sz / n);
  }
  return out;
}

}  // namespace coral
}  // namespace coral_introspection
