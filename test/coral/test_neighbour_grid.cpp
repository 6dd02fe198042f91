// Hash-grid radius search against brute force, 2D and 3D, radii below and above the cell.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "coral_introspection/coral/neighbour_grid.hpp"

using namespace coral_introspection::coral;

namespace {
std::vector<uint32_t> brute(const Points& pts, const Vec3& q, double r, int dim) {
  std::vector<uint32_t> out;
  for (uint32_t i = 0; i < pts.size(); ++i) {
    Vec3 d = pts[i] - q;
    if (dim == 2) d.z() = 0.0;
    if (d.squaredNorm() <= r * r) out.push_back(i);
  }
  return out;
}
}  // namespace

TEST(NeighbourGrid, MatchesBruteForce) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  Points pts;
  for (int i = 0; i < 3000; ++i) pts.emplace_back(u(rng), u(rng), 0.2 * u(rng));
  pts.emplace_back(-1e5, 3e5, 0.0);  // far away (key wrap-around must not matter)
  for (int dim : {2, 3}) {
    const NeighbourGrid grid(pts, 0.5, dim);
    EXPECT_EQ(grid.size(), pts.size());
    for (double r : {0.1, 0.5, 1.3}) {
      for (int k = 0; k < 100; ++k) {
        const Vec3 q(u(rng), u(rng), 0.2 * u(rng));
        std::vector<uint32_t> got;
        grid.forEachWithin(q, r, [&](const Vec3& p, uint32_t i) {
          EXPECT_EQ(p, pts[i]);
          got.push_back(i);
        });
        std::sort(got.begin(), got.end());
        ASSERT_EQ(got, brute(pts, q, r, dim)) << "dim " << dim << " r " << r;
      }
    }
  }
}

// Ties on a 5 cm lattice: a point exactly at the radius passes the rounded distance test
// and must be found although q.x - r rounds into the next cell (q.x = -0.1, p.x = -0.35,
// r = 0.25, cell 0.35: fuzz_coral found CoralPair and computeCoral disagreeing on one).
TEST(NeighbourGrid, FindsLatticePointsExactlyAtTheRadius) {
  Points pts;
  for (int i = -40; i <= 40; ++i)
    for (int j = -40; j <= 40; j += 5) pts.emplace_back(i * 0.05, j * 0.05, 0.0);
  for (int dim : {2, 3}) {
    const NeighbourGrid grid(pts, 0.35, dim);
    int ties = 0;
    for (int qi = -40; qi <= 40; qi += 3)
      for (int ri = 1; ri < 20; ++ri) {
        const Vec3 q(qi * 0.05, 0.0, 0.0);
        const double r = ri * 0.05;
        std::vector<uint32_t> got;
        grid.forEachWithin(q, r, [&](const Vec3&, uint32_t i) { got.push_back(i); });
        std::sort(got.begin(), got.end());
        const std::vector<uint32_t> want = brute(pts, q, r, dim);
        ASSERT_EQ(got, want) << "dim " << dim << " q.x " << q.x() << " r " << r;
        for (uint32_t i : want) ties += (pts[i] - q).squaredNorm() == r * r;
      }
    EXPECT_GT(ties, 100);  // the lattice does put points exactly on the balls
  }
  // The case found by the fuzzer: a point 5e-35 m beyond the ball whose rounded squared
  // distance equals r^2.
  const Points tiny = {Vec3(-5.0602862189302745e-35, -5.0602862189302745e-35, 0.0)};
  const NeighbourGrid g(tiny, 0.35, 2);
  int found = 0;
  g.forEachWithin(Vec3(0.30000000000000004, 0.0, 0.0), 0.30000000000000004,
                  [&](const Vec3&, uint32_t) { ++found; });
  EXPECT_EQ(found, 1);
}

TEST(NeighbourGrid, EmptyCloud) {
  const NeighbourGrid grid(Points{}, 1.0, 3);
  int n = 0;
  grid.forEachWithin(Vec3::Zero(), 10.0, [&](const Vec3&, uint32_t) { ++n; });
  EXPECT_EQ(n, 0);
}

TEST(NeighbourGrid, TwoCloudCellsSplitIntoAThenB) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  Points a, b;
  for (int i = 0; i < 500; ++i) a.emplace_back(u(rng), u(rng), 0.0);
  for (int i = 0; i < 400; ++i) b.emplace_back(u(rng), u(rng), 0.0);
  const NeighbourGrid grid(a, b, 0.7, 2);
  ASSERT_EQ(grid.size(), 900u);
  std::size_t seen_a = 0, seen_b = 0;
  NeighbourGrid::Span spans[2][NeighbourGrid::kBlockCells];
  int num_spans[2];
  for (std::size_t c = 0; c < grid.numCells(); ++c) {
    const NeighbourGrid::Range r = grid.cellPoints(c);
    const uint32_t* idx = grid.cellIndices(c);
    for (const Vec3* p = r.begin; p != r.end; ++p, ++idx) {
      const bool is_a = p < r.mid;
      EXPECT_EQ(is_a, *idx < 500u);
      EXPECT_EQ(*p, is_a ? a[*idx] : b[*idx - 500]);
      (is_a ? seen_a : seen_b)++;
    }
    // The 3x3 neighbour spans hold every point of a (of b) within one cell size of this
    // cell's points, and nothing of the other cloud.
    grid.neighbourSpans(c, spans[0], &num_spans[0], spans[1], &num_spans[1]);
    const Points& sorted = grid.sortedPoints();
    for (int s = 0; s < 2; ++s) {
      const bool of_a = s == 0;
      std::size_t in_spans = 0;
      for (int k = 0; k < num_spans[s]; ++k)
        for (uint32_t i = spans[s][k].begin; i < spans[s][k].end; ++i) {
          EXPECT_EQ(grid.sortedIndices()[i] < 500u, of_a);
          EXPECT_EQ(grid.coordinates(0)[i], sorted[i].x());
          EXPECT_EQ(grid.coordinates(1)[i], sorted[i].y());
          in_spans += (sorted[i] - *r.begin).norm() <= 0.7;
        }
      std::size_t brute_count = 0;
      for (const Vec3& p : of_a ? a : b) brute_count += (p - *r.begin).norm() <= 0.7;
      EXPECT_EQ(in_spans, brute_count);
    }
  }
  EXPECT_EQ(seen_a, 500u);
  EXPECT_EQ(seen_b, 400u);
}

TEST(NeighbourGrid, BallPruningAndHugeCoordinatesStayExact) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-4.0, 4.0);
  Points pts;
  for (int i = 0; i < 2000; ++i) pts.emplace_back(u(rng), u(rng), u(rng));
  // Beyond the clamped cell range: share the outer cell layer, still found exactly.
  for (double big : {1e30, -1e30, 9.3e18, 1e300}) {
    pts.emplace_back(big, 0.0, 0.0);
    pts.emplace_back(big, 0.0, 0.0);
    pts.emplace_back(0.0, big, 1.0);
  }
  const NeighbourGrid grid(pts, 0.3, 3);  // radii up to 4 cells
  for (double r : {0.05, 0.3, 0.45, 1.2}) {
    for (int k = 0; k < 60; ++k) {
      const Vec3 q(u(rng), u(rng), u(rng));
      std::vector<uint32_t> got;
      grid.forEachWithin(q, r, [&](const Vec3&, uint32_t i) { got.push_back(i); });
      std::sort(got.begin(), got.end());
      ASSERT_EQ(got, brute(pts, q, r, 3)) << "r " << r;
    }
  }
  for (const Vec3& q : {Vec3(1e30, 0.0, 0.0), Vec3(0.0, 1e30, 1.0), Vec3(1e300, 0.0, 0.0)}) {
    std::vector<uint32_t> got;
    grid.forEachWithin(q, 0.5, [&](const Vec3&, uint32_t i) { got.push_back(i); });
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, brute(pts, q, 0.5, 3));
  }
}

// Cells more than 2^20 cells from the first point's cell do not fit the packed key of the
// fast table: they go to a second table (grown as they come). A cloud split between two
// places 10^7 m apart is searched exactly in both, and a cluster of 3000 far cells grows
// the second table several times.
TEST(NeighbourGrid, CellsFarFromTheFirstPointAreFoundExactly) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-6.0, 6.0);
  Points pts;
  for (int i = 0; i < 1500; ++i) pts.emplace_back(u(rng), u(rng), 0.1 * u(rng));
  for (int i = 0; i < 3000; ++i) pts.emplace_back(1e7 + 5.0 * u(rng), -3e6 + 5.0 * u(rng), u(rng));
  for (int dim : {2, 3}) {
    const NeighbourGrid grid(pts, 0.25, dim);  // 4e7 cells between the two places
    EXPECT_EQ(grid.size(), pts.size());
    for (const Vec3& centre : {Vec3(0.0, 0.0, 0.0), Vec3(1e7, -3e6, 0.0)}) {
      for (int k = 0; k < 60; ++k) {
        const Vec3 q = centre + Vec3(u(rng), u(rng), 0.1 * u(rng));
        std::vector<uint32_t> got;
        grid.forEachWithin(q, 0.6, [&](const Vec3&, uint32_t i) { got.push_back(i); });
        std::sort(got.begin(), got.end());
        ASSERT_EQ(got, brute(pts, q, 0.6, dim)) << "dim " << dim << " near " << centre.x();
      }
    }
  }
}
