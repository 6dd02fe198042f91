#include "coral_introspection/coral/moments_kernel.hpp"

#include <cstdlib>
#include <cstring>
#include <limits>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define CORAL_AVX2_KERNEL 1
#endif

namespace coral_introspection {
namespace coral {

namespace {

template <int Dim>
void addWithinScalar(const NeighbourGrid& g, const Span* spans, std::size_t num_spans,
                     const Vec3& q, double r2, MomentsN<Dim>* m) {
  const double* x = g.coordinates(0);
  const double* y = g.coordinates(1);
  const double* z = g.coordinates(2);
  for (std::size_t s = 0; s < num_spans; ++s) {
    for (uint32_t i = spans[s].begin; i < spans[s].end; ++i) {
      typename MomentsN<Dim>::V d;
      d(0) = x[i] - q.x();
      d(1) = y[i] - q.y();
      double d2 = d(0) * d(0) + d(1) * d(1);  // the vector path's order of operations
      if constexpr (Dim == 3) {
        d(2) = z[i] - q.z();
        d2 += d(2) * d(2);
      }
      if (d2 <= r2) m->add(d);
    }
  }
}

// The portable vector path: two candidates at a time in GCC / Clang generic vectors of two
// doubles, the width every 64-bit target has natively (SSE2 on any x86-64, NEON on ARM64;
// wider generic vectors are split by the compiler, with worse code). The inside test is a
// lane mask, as in the AVX2 path: no branch per point. |d|^2 is rounded as the
// point-at-a-time path rounds it (the file is built with -ffp-contract=off), so all paths
// count the same points.
using V2 = double __attribute__((vector_size(16)));
using M2 = int64_t __attribute__((vector_size(16)));

template <int Dim>
struct VectorLanes {
  static constexpr int kPairs = Dim * (Dim + 1) / 2;
  V2 n = {}, s[Dim] = {}, s2[kPairs] = {};

  // d: deviations of two points from the query (a lane past a span's end holds +inf).
  __attribute__((always_inline)) void add(const V2* d, V2 rr) {
    V2 d2 = d[0] * d[0] + d[1] * d[1];
    if constexpr (Dim == 3) d2 = d2 + d[2] * d[2];
    const M2 inside = d2 <= rr;  // all bits set in lanes inside the ball
    const V2 one = {1.0, 1.0};
    n += reinterpret_cast<V2>(reinterpret_cast<M2>(one) & inside);
    V2 dm[Dim];
    for (int i = 0; i < Dim; ++i) {
      dm[i] = reinterpret_cast<V2>(reinterpret_cast<M2>(d[i]) & inside);  // +0 outside
      s[i] += dm[i];
    }
    int k = 0;
    for (int i = 0; i < Dim; ++i)
      for (int j = i; j < Dim; ++j, ++k) s2[k] += dm[i] * dm[j];
  }
  void addTo(MomentsN<Dim>* m) const {
    m->n += n[0] + n[1];
    for (int i = 0; i < Dim; ++i) m->sum(i) += s[i][0] + s[i][1];
    int k = 0;
    for (int i = 0; i < Dim; ++i)
      for (int j = i; j < Dim; ++j, ++k) m->sum2(i, j) += s2[k][0] + s2[k][1];
  }
};

template <int Dim>
void addWithinVector(const NeighbourGrid& g, const Span* spans, std::size_t num_spans,
                     const Vec3& q, double r2, MomentsN<Dim>* m) {
  const double* c[Dim];
  V2 qv[Dim];
  for (int a = 0; a < Dim; ++a) {
    c[a] = g.coordinates(a);
    qv[a] = V2{q(a), q(a)};
  }
  const V2 rr = {r2, r2};
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Two accumulators, four points per step: the sums' add latency is not one long chain.
  VectorLanes<Dim> acc[2];
  V2 d[Dim], e[Dim];
  auto load = [&](uint32_t i, V2* out) {
    for (int a = 0; a < Dim; ++a) {
      V2 v;
      std::memcpy(&v, c[a] + i, sizeof v);  // unaligned load
      out[a] = v - qv[a];
    }
  };
  for (std::size_t s = 0; s < num_spans; ++s) {
    uint32_t i = spans[s].begin;
    const uint32_t end = spans[s].end;
    for (; i + 4 <= end; i += 4) {
      load(i, d);
      load(i + 2, e);
      acc[0].add(d, rr);
      acc[1].add(e, rr);
    }
    if (i + 2 <= end) {
      load(i, d);
      acc[0].add(d, rr);
      i += 2;
    }
    if (i < end) {  // one point left: the other lane at +inf is outside (inf > r2)
      for (int a = 0; a < Dim; ++a) d[a] = V2{c[a][i], kInf} - qv[a];
      acc[1].add(d, rr);
    }
  }
  acc[0].addTo(m);
  acc[1].addTo(m);
}

#ifdef CORAL_AVX2_KERNEL
#define CORAL_AVX2 __attribute__((target("avx2,fma")))

// Lanes 0 .. r-1 of a load at kTail + 4 - r are set (r in 1..3): the tail of a span.
const int64_t kTail[8] = {-1, -1, -1, -1, 0, 0, 0, 0};

CORAL_AVX2 inline double sumLanes(__m256d v) {
  const __m128d s = _mm_add_pd(_mm256_castpd256_pd128(v), _mm256_extractf128_pd(v, 1));
  return _mm_cvtsd_f64(_mm_add_sd(s, _mm_unpackhi_pd(s, s)));
}

// |d|^2 of four points, rounded as the portable path rounds it (x^2 + y^2, then + z^2; no
// FMA: the file is compiled with -ffp-contract=off), so both paths count the same points.
template <int Dim>
CORAL_AVX2 inline __m256d squaredNorm(const __m256d* d) {
  __m256d d2 = _mm256_add_pd(_mm256_mul_pd(d[0], d[0]), _mm256_mul_pd(d[1], d[1]));
  if constexpr (Dim == 3) d2 = _mm256_add_pd(d2, _mm256_mul_pd(d[2], d[2]));
  return d2;
}

// Four points' share of the moments, in lanes: n, sum (Dim), upper triangle of sum2
// (xx, xy, [xz,] yy, [yz, zz]).
template <int Dim>
struct Lanes {
  static constexpr int kPairs = Dim * (Dim + 1) / 2;
  __m256d n, s[Dim], s2[kPairs];

  CORAL_AVX2 Lanes() {
    n = _mm256_setzero_pd();
    for (int i = 0; i < Dim; ++i) s[i] = _mm256_setzero_pd();
    for (int i = 0; i < kPairs; ++i) s2[i] = _mm256_setzero_pd();
  }
  // d: deviations of four points from the query; inside: lane mask of the points to add.
  CORAL_AVX2 __attribute__((always_inline)) void add(const __m256d* d, __m256d inside) {
    n = _mm256_add_pd(n, _mm256_and_pd(inside, _mm256_set1_pd(1.0)));
    __m256d dm[Dim];
    for (int i = 0; i < Dim; ++i) {
      dm[i] = _mm256_and_pd(d[i], inside);  // +0 outside: adds nothing
      s[i] = _mm256_add_pd(s[i], dm[i]);
    }
    int k = 0;
    for (int i = 0; i < Dim; ++i)
      for (int j = i; j < Dim; ++j, ++k) s2[k] = _mm256_fmadd_pd(dm[i], dm[j], s2[k]);
  }
  CORAL_AVX2 void addTo(MomentsN<Dim>* m) const {
    m->n += sumLanes(n);
    for (int i = 0; i < Dim; ++i) m->sum(i) += sumLanes(s[i]);
    int k = 0;
    for (int i = 0; i < Dim; ++i)
      for (int j = i; j < Dim; ++j, ++k) m->sum2(i, j) += sumLanes(s2[k]);
  }
};

template <int Dim>
CORAL_AVX2 void addWithinAvx2(const NeighbourGrid& g, const Span* spans, std::size_t num_spans,
                              const Vec3& q, double r2, MomentsN<Dim>* m) {
  const double* c[Dim];
  __m256d qv[Dim];
  for (int a = 0; a < Dim; ++a) {
    c[a] = g.coordinates(a);
    qv[a] = _mm256_set1_pd(q(a));
  }
  const __m256d rr = _mm256_set1_pd(r2);
  Lanes<Dim> acc;
  __m256d d[Dim];
  for (std::size_t s = 0; s < num_spans; ++s) {
    uint32_t i = spans[s].begin;
    const uint32_t end = spans[s].end;
    for (; i + 4 <= end; i += 4) {
      for (int a = 0; a < Dim; ++a) d[a] = _mm256_sub_pd(_mm256_loadu_pd(c[a] + i), qv[a]);
      acc.add(d, _mm256_cmp_pd(squaredNorm<Dim>(d), rr, _CMP_LE_OQ));
    }
    if (i < end) {  // 1-3 points left: masked loads never touch memory past the span
      const __m256i lanes =
          _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kTail + 4 - (end - i)));
      for (int a = 0; a < Dim; ++a)
        d[a] = _mm256_sub_pd(_mm256_maskload_pd(c[a] + i, lanes), qv[a]);
      const __m256d inside = _mm256_cmp_pd(squaredNorm<Dim>(d), rr, _CMP_LE_OQ);
      acc.add(d, _mm256_and_pd(inside, _mm256_castsi256_pd(lanes)));
    }
  }
  acc.addTo(m);
}

bool avx2Supported() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}
#else
bool avx2Supported() { return false; }
#endif

// Fewer candidates than this go one at a time (fewer instructions than masked four-point
// blocks plus the final sum of the lanes: sparse radar cells hold 1-3 points).
constexpr std::size_t kMinVectorCandidates = 8;

// What kBest runs: CORAL_KERNEL=portable (the generic vector path) or scalar (one point at a
// time) in the environment, read once per process; else AVX2 where the processor has it.
MomentKernel bestKernel() {
  static const MomentKernel best = [] {
    const char* env = std::getenv("CORAL_KERNEL");
    if (env != nullptr && std::strcmp(env, "portable") == 0) return MomentKernel::kPortable;
    if (env != nullptr && std::strcmp(env, "scalar") == 0) return MomentKernel::kScalar;
    return avx2Supported() ? MomentKernel::kBest : MomentKernel::kPortable;
  }();
  return best;
}

}  // namespace

const char* momentKernelName() {
  switch (bestKernel()) {
    case MomentKernel::kBest:
      return "avx2";
    case MomentKernel::kPortable:
      return "portable";
    case MomentKernel::kScalar:
      return "scalar";
  }
  return "portable";
}

template <int Dim>
void addWithin(const NeighbourGrid& grid, const Span* spans, std::size_t num_spans, const Vec3& q,
               double r2, MomentsN<Dim>* m, MomentKernel kernel) {
  std::size_t candidates = 0;
  for (std::size_t s = 0; s < num_spans; ++s) candidates += spans[s].end - spans[s].begin;
  if (kernel == MomentKernel::kBest) kernel = bestKernel();
  if (candidates < kMinVectorCandidates) kernel = MomentKernel::kScalar;
#ifdef CORAL_AVX2_KERNEL
  if (kernel == MomentKernel::kBest) {  // bestKernel() says AVX2 is there
    addWithinAvx2<Dim>(grid, spans, num_spans, q, r2, m);
    return;
  }
#endif
  if (kernel == MomentKernel::kScalar)
    addWithinScalar<Dim>(grid, spans, num_spans, q, r2, m);
  else
    addWithinVector<Dim>(grid, spans, num_spans, q, r2, m);
}

template <int Dim>
std::size_t momentsNear(const NeighbourGrid& grid, const Vec3& q, double radius, MomentsN<Dim>* a,
                        MomentsN<Dim>* b) {
  // The kernel runs on batches of spans (one call per query in practice: a query visits at
  // most 4^3 cells unless its radius exceeds the cell size).
  constexpr std::size_t kBatch = 64;
  Span sa[kBatch], sb[kBatch];
  std::size_t na = 0, nb = 0, tests = 0;
  const double r2 = radius * radius;
  auto flush = [&] {
    if (na > 0) addWithin<Dim>(grid, sa, na, q, r2, a);
    if (nb > 0) addWithin<Dim>(grid, sb, nb, q, r2, b);
    na = nb = 0;
  };
  grid.forEachCellNear(q, radius, [&](const NeighbourGrid::Range& rg) {
    const uint32_t begin = grid.position(rg.begin), mid = grid.position(rg.mid),
                   end = grid.position(rg.end);
    tests += end - begin;
    if (b == nullptr) {
      sa[na++] = {begin, end};
    } else {
      if (mid > begin) sa[na++] = {begin, mid};
      if (end > mid) sb[nb++] = {mid, end};
    }
    if (na == kBatch || nb == kBatch) flush();
  });
  flush();
  return tests;
}

template void addWithin<2>(const NeighbourGrid&, const Span*, std::size_t, const Vec3&, double,
                           MomentsN<2>*, MomentKernel);
template void addWithin<3>(const NeighbourGrid&, const Span*, std::size_t, const Vec3&, double,
                           MomentsN<3>*, MomentKernel);
template std::size_t momentsNear<2>(const NeighbourGrid&, const Vec3&, double, MomentsN<2>*,
                                    MomentsN<2>*);
template std::size_t momentsNear<3>(const NeighbourGrid&, const Vec3&, double, MomentsN<3>*,
                                    MomentsN<3>*);

}  // namespace coral
}  // namespace coral_introspection
