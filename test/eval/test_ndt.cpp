// NDT score (Eq. 11) and Rel-NDT entropy on known configurations.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "coral_introspection/coral/entropy.hpp"
#include "coral_introspection/eval/ndt.hpp"
#include "coral_introspection/eval/synthetic.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::eval;

namespace {
Points shifted(const Points& p, const Vec3& d) {
  Points out;
  for (const Vec3& x : p) out.push_back(x + d);
  return out;
}
Points yardScan(unsigned seed) {
  std::mt19937 rng(seed);
  return simulateScan(SyntheticScene::structuredYard(),
                      Eigen::Isometry3d(Eigen::Translation3d(0, 0, 1.0)), LidarModel(), rng);
}
}  // namespace

TEST(Ndt, SingleGaussianCellGivesTheAnalyticDensity) {
  // 2D: 5 points in one voxel; mean (0.5, 0.5); the density at the mean is
  // 1 / (2 pi sqrt(det Sigma)) with the sample covariance (1/(n-1)).
  Points a = {{0.3, 0.5, 0}, {0.7, 0.5, 0}, {0.5, 0.3, 0}, {0.5, 0.7, 0}, {0.5, 0.5, 0}};
  NdtConfig cfg;
  cfg.dimension = 2;
  cfg.voxel_size = 1.0;
  const NdtResult r = computeNdtScore(a, {{0.5, 0.5, 0.0}}, cfg);
  ASSERT_TRUE(r.valid);
  EXPECT_EQ(r.num_cells, 1u);
  EXPECT_EQ(r.num_overlap, 1u);
  const double var = 0.08 / 4.0;  // sum of squares 2 * 0.04 over n - 1 = 4, per axis
  EXPECT_NEAR(r.score, 1.0 / (2.0 * M_PI * var), 1e-9);
  double h = 0.0;
  ASSERT_TRUE(differentialEntropy(Mat3(Vec3(var, var, 1.0).asDiagonal()), 2, 0.0, &h));
  EXPECT_NEAR(r.entropy, h, 1e-9);  // Rel-NDT entropy = Eq. 1 of the cell
  // A point two voxels away is not overlapping; one in a neighbour voxel is.
  EXPECT_FALSE(computeNdtScore(a, {{2.5, 0.5, 0.0}}, cfg).valid);
  const NdtResult nb = computeNdtScore(a, {{1.5, 0.5, 0.0}}, cfg);
  ASSERT_TRUE(nb.valid);
  EXPECT_NEAR(nb.score, std::exp(-0.5 * 1.0 / var) / (2.0 * M_PI * var), 1e-12);
}

TEST(Ndt, SelfScoreHigherThanShiftedCopy) {
  const Points a = yardScan(1), b = yardScan(2);  // two samplings of one scene
  NdtConfig cfg;                                  // 3D, v = 0.6 m
  const NdtResult aligned = computeNdtScore(a, b, cfg);
  ASSERT_TRUE(aligned.valid);
  EXPECT_GT(aligned.num_cells, 50u);
  for (double d : {0.1, 0.3}) {
    const NdtResult mis = computeNdtScore(a, shifted(b, Vec3(d, d, 0.0)), cfg);
    ASSERT_TRUE(mis.valid);
    EXPECT_GT(aligned.score, 1.5 * mis.score) << "shift " << d;
  }
}

TEST(Ndt, InvalidConfigAndEmptyInput) {
  NdtConfig cfg;
  cfg.min_points = 2;
  EXPECT_NE(cfg.validate().find("min_points"), std::string::npos);
  EXPECT_FALSE(computeNdtScore({}, {{0, 0, 0}}, NdtConfig()).valid);
}
