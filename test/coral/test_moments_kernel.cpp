// CorAl's moment kernel (coral/moments_kernel.hpp): every path (AVX2 and generic vectors four
// points at a time, scalar one at a time) against brute force, on random clouds, short spans (the
// masked tail of the vector path), ties exactly at the radius and joint two-cloud grids.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "coral_introspection/coral/moments_kernel.hpp"

using namespace coral_introspection::coral;

namespace {

template <int Dim>
MomentsN<Dim> bruteMoments(const Points& pts, const Vec3& q, double r2) {
  MomentsN<Dim> m;
  for (const Vec3& p : pts) {
    typename MomentsN<Dim>::V d = (p - q).template head<Dim>();
    double d2 = d(0) * d(0) + d(1) * d(1);
    if (Dim == 3) d2 += d(Dim - 1) * d(Dim - 1);
    if (d2 <= r2) m.add(d);
  }
  return m;
}

template <int Dim>
void expectSame(const MomentsN<Dim>& got, const MomentsN<Dim>& want, const char* what) {
  ASSERT_EQ(got.n, want.n) << what;  // the same points, ties included
  for (int i = 0; i < Dim; ++i) {
    EXPECT_NEAR(got.sum(i), want.sum(i), 1e-9) << what;
    for (int j = i; j < Dim; ++j) EXPECT_NEAR(got.sum2(i, j), want.sum2(i, j), 1e-9) << what;
  }
}

// The grid's points split into spans of 1..9 points (lengths hit every tail of a 4-point
// block), every point in exactly one span.
std::vector<Span> shortSpans(std::size_t n, std::mt19937& rng) {
  std::vector<Span> spans;
  std::uniform_int_distribution<uint32_t> len(1, 9);
  for (uint32_t b = 0; b < n;) {
    const uint32_t e = std::min<uint32_t>(static_cast<uint32_t>(n), b + len(rng));
    spans.push_back({b, e});
    b = e;
  }
  return spans;
}

template <int Dim>
void checkBothPaths(const Points& pts, const std::vector<Vec3>& queries, double r, int seed) {
  const NeighbourGrid grid(pts, 0.5, Dim);
  std::mt19937 rng(seed);
  const std::vector<Span> spans = shortSpans(pts.size(), rng);
  for (const Vec3& q : queries) {
    const MomentsN<Dim> want = bruteMoments<Dim>(pts, q, r * r);
    for (MomentKernel k : {MomentKernel::kBest, MomentKernel::kPortable, MomentKernel::kScalar}) {
      MomentsN<Dim> got;
      addWithin<Dim>(grid, spans.data(), spans.size(), q, r * r, &got, k);
      expectSame(got, want,
                 k == MomentKernel::kBest       ? "best kernel"
                 : k == MomentKernel::kPortable ? "portable kernel"
                                                : "scalar kernel");
    }
  }
}

}  // namespace

TEST(MomentKernel, BothPathsMatchBruteForceOnRandomClouds) {
  std::printf("moment kernel on this machine: %s\n", momentKernelName());
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  Points pts;
  for (int i = 0; i < 1500; ++i) pts.emplace_back(u(rng), u(rng), 0.3 * u(rng));
  std::vector<Vec3> queries;
  for (int i = 0; i < 40; ++i) queries.emplace_back(u(rng), u(rng), 0.3 * u(rng));
  checkBothPaths<3>(pts, queries, 0.7, 1);
  checkBothPaths<2>(pts, queries, 0.7, 2);
}

TEST(MomentKernel, TiesExactlyAtTheRadiusCountAlikeInBothPaths) {
  // A 0.1 m lattice and lattice queries: many neighbours at exactly the radius, whose
  // rounded |p - q|^2 equals r^2 or misses it by an ulp. Both paths must round it as
  // (x^2 + y^2) + z^2 does: with fused multiply-adds some of these pairs change sides.
  Points pts;
  for (int x = -12; x <= 12; ++x)
    for (int y = -12; y <= 12; ++y)
      for (int z = -4; z <= 4; ++z) pts.emplace_back(0.1 * x, 0.1 * y, 0.1 * z);
  std::vector<Vec3> queries;
  for (int k = -5; k <= 5; ++k) queries.emplace_back(0.1 * k, -0.1 * k, 0.0);
  int fma_flips = 0;  // pairs a fused multiply-add would put on the other side of r
  for (double r : {0.5, 0.9}) {
    checkBothPaths<3>(pts, queries, r, 3);
    checkBothPaths<2>(pts, queries, r, 4);
    for (const Vec3& q : queries)
      for (const Vec3& p : pts) {
        const Vec3 d = p - q;
        const double plain = d.x() * d.x() + d.y() * d.y() + d.z() * d.z();
        const double fused = std::fma(d.z(), d.z(), std::fma(d.x(), d.x(), d.y() * d.y()));
        fma_flips += (plain <= r * r) != (fused <= r * r);
      }
  }
  EXPECT_GT(fma_flips, 0);  // the lattice does tell the two roundings apart
}

TEST(MomentKernel, MomentsNearSplitsAJointGridByCloud) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  Points a, b;
  for (int i = 0; i < 800; ++i) a.emplace_back(u(rng), u(rng), 0.2 * u(rng));
  for (int i = 0; i < 600; ++i) b.emplace_back(u(rng), u(rng), 0.2 * u(rng));
  const NeighbourGrid joint(a, b, 1.0, 3), only_a(a, 1.0, 3);
  for (int k = 0; k < 50; ++k) {
    const Vec3 q(u(rng), u(rng), 0.2 * u(rng));
    const double r = 0.4 + 0.01 * k;  // below and above the cell size
    MomentsN<3> ma, mb, alone;
    const std::size_t tests = momentsNear<3>(joint, q, r, &ma, &mb);
    momentsNear<3>(only_a, q, r, &alone);
    expectSame(ma, bruteMoments<3>(a, q, r * r), "cloud a of the joint grid");
    expectSame(mb, bruteMoments<3>(b, q, r * r), "cloud b of the joint grid");
    expectSame(alone, ma, "one-cloud grid");
    EXPECT_GE(tests, static_cast<std::size_t>(ma.n + mb.n));
    EXPECT_LE(tests, a.size() + b.size());
  }
}
