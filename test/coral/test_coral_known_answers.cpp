// CorAl on tiny point sets whose per-point entropies are known in closed form (Eq. 1-6):
// every neighbourhood is a whole group of points, so h_sep and h_joint of each point follow
// from the group's sample covariance by hand. Catches a swapped own / other neighbourhood,
// a relaxed min_neighbours_other and a missing min_overlap gate, which the scene-level tests
// do not see. Only the public API (computeCoral, CoralConfig, CoralResult) is used.
#include <gtest/gtest.h>

#include <cmath>

#include "coral_introspection/coral/coral.hpp"

using namespace coral_introspection::coral;

namespace {

const double kLog2PiE = std::log(2.0 * M_PI * M_E);

// Eq. 1 for a diagonal covariance: h = 1/2 (N ln(2 pi e) + ln(det Sigma + epsilon)).
double entropyOfDiagonal(std::initializer_list<double> variances, double epsilon) {
  double det = 1.0;
  for (double v : variances) det *= v;
  return 0.5 * (variances.size() * kLog2PiE + std::log(det + epsilon));
}

// Every field spelled out: the expected values below depend on each of them.
CoralConfig knownConfig(int dimension, double epsilon) {
  CoralConfig c;
  c.dimension = dimension;
  c.radius = 1.0;  // every group below fits in it with >= 0.12 m to spare, groups are >= 5 m apart
  c.dynamic_radius = false;
  c.epsilon = epsilon;
  c.e_reject = 0.0;
  c.min_neighbours = 4;
  c.min_neighbours_other = 2;
  c.aggregation = Aggregation::kMean;
  c.min_overlap = 0.05;
  c.per_point = true;
  return c;
}

void addRectangle(Points* pts, double cx, double cy, double hx, double hy) {
  for (double sx : {-1.0, 1.0})
    for (double sy : {-1.0, 1.0}) pts->push_back(Vec3(cx + sx * hx, cy + sy * hy, 0.0));
}

// Isolated points on a line far from everything else (no neighbour in either cloud).
void addIsolated(Points* pts, int n, double x0) {
  for (int i = 0; i < n; ++i) pts->push_back(Vec3(x0, 100.0 + 5.0 * i, 0.0));
}

}  // namespace

// 2D. Group 1 at the origin: a = square (+-0.2, +-0.2), b = rectangle (+-0.4, +-0.15). Every
// point of group 1 sees all 4 points of its own cloud and all 4 of the other:
//   Sigma_a = diag(4 * 0.04, 4 * 0.04) / 3,  Sigma_b = diag(4 * 0.16, 4 * 0.0225) / 3,
//   Sigma_joint = diag(4 * 0.04 + 4 * 0.16, 4 * 0.04 + 4 * 0.0225) / 7  (mean 0, n - 1).
// Group 2 at x = 10: a = square (+-0.2) around (10, 0), b = one point (10, 0.5). Each a point
// has its 4 own neighbours but only 1 in b (< min_neighbours_other = 2); the b point has 1
// own neighbour (< min_neighbours = 4): none of the 5 overlaps.
TEST(CoralKnownAnswers, PerPointEntropiesOfTwoGroups2D) {
  Scan a, b;
  addRectangle(&a.points, 0.0, 0.0, 0.2, 0.2);
  addRectangle(&a.points, 10.0, 0.0, 0.2, 0.2);
  addRectangle(&b.points, 0.0, 0.0, 0.4, 0.15);
  b.points.push_back(Vec3(10.0, 0.5, 0.0));
  const CoralResult r = computeCoral(a, b, knownConfig(2, 0.0));

  const double h_a = entropyOfDiagonal({0.16 / 3, 0.16 / 3}, 0.0);
  const double h_b = entropyOfDiagonal({0.64 / 3, 0.09 / 3}, 0.0);
  const double h_joint = entropyOfDiagonal({0.8 / 7, 0.25 / 7}, 0.0);
  ASSERT_GT(std::abs(h_a - h_b), 0.3);  // own and other neighbourhoods are distinguishable

  ASSERT_EQ(r.num_points_a, 8u);
  ASSERT_EQ(r.num_points_b, 5u);
  ASSERT_EQ(r.per_point.size(), 13u);
  for (int i = 0; i < 4; ++i) {  // group 1 of a, then of b (b's points follow a's)
    for (int k : {i, 8 + i}) {
      const PointEntropy& pe = r.per_point[k];
      ASSERT_TRUE(pe.valid) << "point " << k;
      EXPECT_NEAR(pe.h_sep, k < 8 ? h_a : h_b, 1e-5) << "point " << k;
      EXPECT_NEAR(pe.h_joint, h_joint, 1e-5) << "point " << k;
      EXPECT_NEAR(pe.q(), h_joint - (k < 8 ? h_a : h_b), 1e-5) << "point " << k;  // Eq. 6
      EXPECT_FLOAT_EQ(pe.radius, 1.0f);
    }
  }
  for (int k : {4, 5, 6, 7, 12}) EXPECT_FALSE(r.per_point[k].valid) << "group 2 point " << k;

  EXPECT_EQ(r.num_overlap, 8u);
  EXPECT_EQ(r.num_valid, 8u);
  EXPECT_NEAR(r.overlap, 8.0 / 13.0, 1e-12);
  EXPECT_TRUE(r.valid);
  EXPECT_NEAR(r.h_sep, 0.5 * (h_a + h_b), 1e-5);              // Eq. 4 over the valid points
  EXPECT_NEAR(r.h_joint, h_joint, 1e-5);                      // Eq. 3
  EXPECT_NEAR(r.quality, h_joint - 0.5 * (h_a + h_b), 1e-5);  // Eq. 5
  // MME: the joint entropy of every point with >= min_neighbours joint neighbours, overlap
  // or not. Group 2 has 5 joint points with mean (10, 0.1): sum dx^2 = 4 * 0.04 = 0.16,
  // sum dy^2 = 2 * 0.1^2 + 2 * 0.3^2 + 0.4^2 = 0.36, sum dx dy = 0.
  const double h_group2 = entropyOfDiagonal({0.16 / 4, 0.36 / 4}, 0.0);
  EXPECT_NEAR(r.mme, (8 * h_joint + 5 * h_group2) / 13, 1e-5);
}

// Lowering min_neighbours_other to 1 makes group 2's a points overlap: their joint
// neighbourhood is the 5 points of group 2, their own the square.
TEST(CoralKnownAnswers, OneOtherNeighbourCountsOnlyWhenConfigured) {
  Scan a, b;
  addRectangle(&a.points, 10.0, 0.0, 0.2, 0.2);
  b.points.push_back(Vec3(10.0, 0.5, 0.0));
  CoralConfig cfg = knownConfig(2, 0.0);
  CoralResult r = computeCoral(a, b, cfg);
  EXPECT_EQ(r.num_overlap, 0u);
  EXPECT_EQ(r.num_valid, 0u);
  EXPECT_FALSE(r.valid);
  cfg.min_neighbours_other = 1;
  r = computeCoral(a, b, cfg);
  EXPECT_EQ(r.num_overlap, 4u);
  ASSERT_EQ(r.num_valid, 4u);
  EXPECT_TRUE(r.valid);
  EXPECT_NEAR(r.h_sep, entropyOfDiagonal({0.16 / 3, 0.16 / 3}, 0.0), 1e-5);
  EXPECT_NEAR(r.h_joint, entropyOfDiagonal({0.16 / 4, 0.36 / 4}, 0.0), 1e-5);
  EXPECT_FALSE(r.per_point[4].valid);  // b's single point: 1 own neighbour < 4
}

// 3D: a = cube (+-0.2)^3, b = box (+-0.4, +-0.15, +-0.1), both centred at the origin, all
// 16 points within 1 m of each other.
TEST(CoralKnownAnswers, PerPointEntropiesOfBoxes3D) {
  const double eps = 0.0;
  Scan a, b;
  for (double sx : {-1.0, 1.0})
    for (double sy : {-1.0, 1.0})
      for (double sz : {-1.0, 1.0}) {
        a.points.push_back(Vec3(0.2 * sx, 0.2 * sy, 0.2 * sz));
        b.points.push_back(Vec3(0.4 * sx, 0.15 * sy, 0.1 * sz));
      }
  const CoralResult r = computeCoral(a, b, knownConfig(3, eps));
  const double h_a = entropyOfDiagonal({0.32 / 7, 0.32 / 7, 0.32 / 7}, eps);
  const double h_b = entropyOfDiagonal({1.28 / 7, 0.18 / 7, 0.08 / 7}, eps);
  const double h_joint = entropyOfDiagonal({1.6 / 15, 0.5 / 15, 0.4 / 15}, eps);
  ASSERT_EQ(r.per_point.size(), 16u);
  for (int k = 0; k < 16; ++k) {
    const PointEntropy& pe = r.per_point[k];
    ASSERT_TRUE(pe.valid) << "point " << k;
    EXPECT_NEAR(pe.h_sep, k < 8 ? h_a : h_b, 1e-5) << "point " << k;
    EXPECT_NEAR(pe.h_joint, h_joint, 1e-5) << "point " << k;
  }
  EXPECT_TRUE(r.valid);
  EXPECT_NEAR(r.overlap, 1.0, 1e-12);
  EXPECT_NEAR(r.quality, h_joint - 0.5 * (h_a + h_b), 1e-5);
}

// A pair whose overlapping part is too small gives no verdict (DESIGN: "refuse a verdict
// when it is too low"), even though its few overlapping points have finite entropies.
// 8 overlapping points of group 1 plus n isolated points per cloud: overlap 8 / (8 + 2n).
TEST(CoralKnownAnswers, LowOverlapPairIsInvalid) {
  auto pair = [](int isolated) {
    Scan a, b;
    addRectangle(&a.points, 0.0, 0.0, 0.2, 0.2);
    addRectangle(&b.points, 0.0, 0.0, 0.4, 0.15);
    addIsolated(&a.points, isolated, 50.0);
    addIsolated(&b.points, isolated, 60.0);
    return computeCoral(a, b, knownConfig(2, 0.0));
  };
  const CoralResult low = pair(80);  // overlap 8 / 168 = 0.048 < min_overlap 0.05
  EXPECT_EQ(low.num_overlap, 8u);
  EXPECT_EQ(low.num_valid, 8u);
  EXPECT_NEAR(low.overlap, 8.0 / 168.0, 1e-12);
  EXPECT_FALSE(low.valid);
  const CoralResult enough = pair(70);  // 8 / 148 = 0.054
  EXPECT_NEAR(enough.overlap, 8.0 / 148.0, 1e-12);
  EXPECT_TRUE(enough.valid);
  // The same entropies either way: only the verdict is withheld.
  EXPECT_DOUBLE_EQ(low.quality, enough.quality);
  CoralConfig strict = knownConfig(2, 0.0);
  strict.min_overlap = 0.5;
  Scan a, b;
  addRectangle(&a.points, 0.0, 0.0, 0.2, 0.2);
  addRectangle(&b.points, 0.0, 0.0, 0.4, 0.15);
  addIsolated(&a.points, 3, 50.0);
  addIsolated(&b.points, 3, 60.0);  // overlap 8 / 14 = 0.57
  EXPECT_TRUE(computeCoral(a, b, strict).valid);
  addIsolated(&b.points, 4, 70.0);  // overlap 8 / 18 = 0.44
  EXPECT_FALSE(computeCoral(a, b, strict).valid);
}

// The default config (every field default) needs two other-cloud neighbours: five points of
// a within 0.15 m of each other (inside the default 0.3 m radius) and one point of b among
// them do not overlap; a second point of b makes the five a points overlap (b's two points,
// with 2 own neighbours < min_neighbours 4, still do not).
TEST(CoralKnownAnswers, DefaultConfigNeedsTwoOtherNeighbours) {
  Scan a, b;
  for (const Vec3& p :
       {Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0, 0.1, 0), Vec3(0, 0, 0.1), Vec3(0.05, 0.05, 0.05)})
    a.points.push_back(p);
  b.points.push_back(Vec3(0.02, 0.03, 0.04));
  const CoralConfig defaults;
  CoralResult r = computeCoral(a, b, defaults);
  EXPECT_EQ(r.num_overlap, 0u);
  EXPECT_FALSE(r.valid);
  b.points.push_back(Vec3(0.06, 0.02, 0.01));
  r = computeCoral(a, b, defaults);
  EXPECT_EQ(r.num_overlap, 5u);
  EXPECT_TRUE(r.valid);
}
