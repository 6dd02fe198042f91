// CFEAR-style surface points and P2P / P2L / P2D scores (Sec. V-A b) with known answers.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

#include "coral_introspection/eval/cfear_scores.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::eval;

namespace {
SurfacePoint surface(const Eigen::Vector2d& mean, const Eigen::Matrix2d& cov) {
  SurfacePoint s;
  s.mean = mean;
  s.cov = cov;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
  s.normal = es.eigenvectors().col(0);
  return s;
}
// Two perpendicular noisy walls plus a scatter of posts, like a street corner.
Points corner(unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 0.05);
  Points p;
  for (double s = 0; s < 40; s += 0.25) {
    p.emplace_back(s + g(rng), 10.0 + g(rng), 0.0);
    p.emplace_back(-5.0 + g(rng), s - 20 + g(rng), 0.0);
  }
  for (int i = 0; i < 12; ++i)
    for (int k = 0; k < 8; ++k) p.emplace_back(3.0 * i + g(rng), -8.0 + 0.3 * k + g(rng), 0.0);
  return p;
}
}  // namespace

TEST(CfearScores, ResidualsVanishOnTheSurface) {
  Eigen::Matrix2d cov;
  cov << 2.0, 0.9, 0.9, 0.6;  // a tilted line-like surface
  const SurfacePoint s = surface({1.0, 2.0}, cov);
  EXPECT_DOUBLE_EQ(p2dCost(s, s.mean), 0.0);  // P2D of a point at the mean is 0
  EXPECT_DOUBLE_EQ(p2pCost(s, s.mean), 0.0);
  // A point on the surface line (along the tangent) has zero P2L, non-zero P2P.
  const Eigen::Vector2d tangent(-s.normal.y(), s.normal.x());
  const Eigen::Vector2d on_line = s.mean + 3.0 * tangent;
  EXPECT_NEAR(p2lCost(s, on_line), 0.0, 1e-20);
  EXPECT_NEAR(p2pCost(s, on_line), 9.0, 1e-12);
  EXPECT_NEAR(p2lCost(s, s.mean + 0.5 * s.normal), 0.25, 1e-12);
}

TEST(CfearScores, P2dIsTheMahalanobisDistanceForANonDiagonalCovariance) {
  Eigen::Matrix2d cov;
  cov << 2.0, 0.9, 0.9, 0.6;
  const SurfacePoint s = surface({0.0, 0.0}, cov);
  for (const Eigen::Vector2d& r :
       {Eigen::Vector2d(1.0, 0.0), Eigen::Vector2d(0.3, -0.7), Eigen::Vector2d(-2.0, 1.5)}) {
    const double expected = r.dot(cov.inverse() * r);
    EXPECT_NEAR(p2dCost(s, r), expected, 1e-12 * (1.0 + expected));
    // The untransposed factor gives a different (wrong) value here.
    const Eigen::Matrix2d L = Eigen::LLT<Eigen::Matrix2d>(cov.inverse()).matrixL();
    EXPECT_GT(std::abs((L * r).squaredNorm() - expected), 1e-3);
  }
}

TEST(CfearScores, SurfacePointsOfAWallHaveItsNormal) {
  Points wall;
  for (double x = 0; x < 20; x += 0.2) wall.emplace_back(x, 5.0, 0.0);
  const SurfacePoints sp = computeSurfacePoints(wall, CfearConfig());
  ASSERT_EQ(sp.size(), 7u);  // one per occupied 3 m cell along x in [0, 20)
  // Deterministic: a second run gives the same surfaces (cell sums start at zero).
  const SurfacePoints again = computeSurfacePoints(wall, CfearConfig());
  for (std::size_t i = 0; i < sp.size(); ++i) EXPECT_EQ(sp[i].mean, again[i].mean);
  for (const SurfacePoint& s : sp) {
    EXPECT_NEAR(s.mean.y(), 5.0, 1e-9);
    EXPECT_NEAR(std::abs(s.normal.y()), 1.0, 1e-9);
    EXPECT_GE(s.num_points, 6);
  }
}

TEST(CfearScores, AlignedScoresBetterThanMisaligned) {
  const CfearConfig cfg;
  const SurfacePoints a = computeSurfacePoints(corner(1), cfg);
  const SurfacePoints b = computeSurfacePoints(corner(2), cfg);  // same scene, new noise
  ASSERT_GT(a.size(), 10u);
  const CfearScores ok = computeCfearScores(a, b, cfg);
  ASSERT_TRUE(ok.valid);
  const SurfacePoints b_mis = transformSurfacePoints(b, se2(0.5, 0.5, 0.0));
  const CfearScores mis = computeCfearScores(a, b_mis, cfg);
  ASSERT_TRUE(mis.valid);
  EXPECT_LT(ok.p2p.normalized, mis.p2p.normalized);
  EXPECT_LT(ok.p2l.normalized, mis.p2l.normalized);
  EXPECT_LT(ok.p2d.normalized, mis.p2d.normalized);
  EXPECT_DOUBLE_EQ(ok.p2p.normalized, ok.p2p.sum / ok.p2p.count);
  // A surface set against itself: every residual is 0.
  const CfearScores self = computeCfearScores(a, a, cfg);
  EXPECT_DOUBLE_EQ(self.p2d.sum, 0.0);
  EXPECT_DOUBLE_EQ(self.p2p.count, static_cast<double>(a.size()));
}

TEST(CfearScores, TransformMovesMeansCovariancesAndNormals) {
  Eigen::Matrix2d cov;
  cov << 2.0, 0.0, 0.0, 0.1;
  const SurfacePoints s = {surface({1.0, 0.0}, cov)};
  const SurfacePoints t = transformSurfacePoints(s, se2(0.0, 1.0, M_PI / 2));
  EXPECT_NEAR((t[0].mean - Eigen::Vector2d(0.0, 2.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(t[0].cov(1, 1), 2.0, 1e-12);
  EXPECT_NEAR(std::abs(t[0].normal.x()), 1.0, 1e-12);
}
