// CorAl's inner loop (91-99 % of a pair's instructions before the lidar work, ~60 % of a
// 64-beam pair's time after it): the moments (count, sum, sum of outer products, centred on
// the query) of the points of a few grid cells that lie within the query's radius.
//
// Three implementations of the same sums: on x86-64 processors with AVX2 and FMA (checked at
// run time, so the package still runs on any x86-64) four points per instruction and no
// branch per point (a point's inside/outside test is a lane mask, not a jump: about 40 % of
// the candidates of a lidar query are inside, which a branch predicts badly); elsewhere the
// same branch-free blocks, two points wide, in the compiler's generic vectors (SSE2 on any x86-64,
// NEON on ARM64): `portable`; and one point at a time (`scalar`). All count exactly the same
// points (|p - q|^2 is rounded alike) and add them in different orders, so their moments
// differ by rounding only. Calls with fewer than 8 candidates always take the scalar path
// (fewer instructions). CORAL_KERNEL=portable or scalar in the environment forces that path
// everywhere (benchmarks; read once per process).
#pragma once

#include <cstddef>
#include <cstdint>

#include "coral_introspection/coral/entropy.hpp"
#include "coral_introspection/coral/neighbour_grid.hpp"

namespace coral_introspection {
namespace coral {

using Span = NeighbourGrid::Span;

enum class MomentKernel {
  kBest,      // AVX2 where the processor has it, else kPortable (or as CORAL_KERNEL says)
  kPortable,  // branch-free four-point blocks in generic vectors
  kScalar,    // one point at a time
};

// The kernel kBest resolves to in this process ("avx2", "portable" or "scalar").
const char* momentKernelName();

// Adds to *m every point p of the spans with |p - q|^2 <= r2, as the deviation p - q
// (Dim 2: x and y only). Distance tests: the spans' total length.
template <int Dim>
void addWithin(const NeighbourGrid& grid, const Span* spans, std::size_t num_spans, const Vec3& q,
               double r2, MomentsN<Dim>* m, MomentKernel kernel = MomentKernel::kBest);

// Moments of the points within `radius` of q in one grid: with b null, of every point (a
// grid of one cloud) into *a; otherwise of cloud a's and cloud b's part of each cell (a
// joint grid) into *a and *b. Returns the distance tests (points of the visited cells).
template <int Dim>
std::size_t momentsNear(const NeighbourGrid& grid, const Vec3& q, double radius, MomentsN<Dim>* a,
                        MomentsN<Dim>* b = nullptr);

}  // namespace coral
}  // namespace coral_introspection
