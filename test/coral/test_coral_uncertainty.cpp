// Uncertainty-aware CorAl: the isotropic special case equals CorAl's dynamic radius, and
// on a simulated planar radar the aligned pair scores below misaligned ones.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "coral_introspection/coral/coral_uncertainty.hpp"
#include "coral_introspection/eval/oxford_dataset.hpp"
#include "coral_introspection/eval/oxford_training.hpp"
#include "coral_introspection/eval/synthetic.hpp"
#include "coral_introspection/radar/radar_uncertainty.hpp"
#include "coral_introspection/radar/rip_features.hpp"
#include "support/test_data.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::radar;
using namespace coral_introspection::eval;

namespace {

struct Pair {
  Scan a, b;  // b in its own sensor frame
  Eigen::Isometry3d T_a_b;
};

Pair simulatePair(unsigned seed) {
  std::mt19937 rng(seed);
  const SyntheticScene scene = SyntheticScene::structuredYard();
  LidarModel planar;
  planar.rings = 1;  // spinning 2D sensor
  planar.azimuths = 1440;
  planar.range_noise = 0.03;
  Pair p;
  const Eigen::Isometry3d T_w_a = se2(-2.0, 0.5, 0.1), T_w_b = se2(-1.0, 1.0, 0.2);
  p.a.points = simulateScan(scene, T_w_a, planar, rng);
  p.b.points = simulateScan(scene, T_w_b, planar, rng);
  p.T_a_b = T_w_a.inverse() * T_w_b;
  RadarNoiseConfig noise;
  noise.sigma_range = 0.03;
  noise.sigma_azimuth = 0.01;
  std::string err;
  EXPECT_TRUE(attachCovariances(p.a, noise, 2, &err)) << err;
  EXPECT_TRUE(attachCovariances(p.b, noise, 2, &err)) << err;
  return p;
}

UncertainCoralConfig planarConfig() {
  UncertainCoralConfig cfg;
  cfg.base.dimension = 2;
  cfg.base.r_min = 0.3;
  cfg.base.r_max = 1.0;
  return cfg;
}

}  // namespace

TEST(CoralUncertainty, IsotropicCovarianceIsTheDynamicRadius) {
  Pair p = simulatePair(1);
  UncertainCoralConfig cfg = planarConfig();
  cfg.base.dynamic_radius = true;
  cfg.base.alpha_deg = 2.0;
  // Sigma_k = (d sin(alpha) / gate)^2 I gives semi-axes clamp(d sin(alpha), r_min, r_max).
  for (Scan* s : {&p.a, &p.b})
    for (std::size_t i = 0; i < s->points.size(); ++i) {
      const double r = s->points[i].head<2>().norm() * std::sin(cfg.base.alpha_deg * M_PI / 180);
      s->covariances[i] = std::pow(r / cfg.gate_sigma, 2) * Mat3::Identity();
    }
  const Scan b_in_a = transformScan(p.b, p.T_a_b);
  const CoralResult u = computeCoralUncertain(p.a, b_in_a, cfg);
  const CoralResult c = computeCoral(p.a, b_in_a, cfg.base);
  ASSERT_TRUE(c.valid);
  ASSERT_TRUE(u.valid);
  EXPECT_EQ(u.num_valid, c.num_valid);
  EXPECT_EQ(u.num_overlap, c.num_overlap);
  EXPECT_NEAR(u.h_joint, c.h_joint, 1e-6);
  EXPECT_NEAR(u.h_sep, c.h_sep, 1e-6);
  EXPECT_NEAR(u.quality, c.quality, 1e-6);
}

TEST(CoralUncertainty, WithoutCovariancesFallsBackToPlainCoral) {
  Pair p = simulatePair(2);
  p.a.covariances.clear();
  p.b.covariances.clear();
  const UncertainCoralConfig cfg = planarConfig();
  const Scan b_in_a = transformScan(p.b, p.T_a_b);
  const CoralResult u = computeCoralUncertain(p.a, b_in_a, cfg);
  const CoralResult c = computeCoral(p.a, b_in_a, cfg.base);
  EXPECT_EQ(u.num_valid, c.num_valid);
  EXPECT_NEAR(u.quality, c.quality, 1e-6);
}

TEST(CoralUncertainty, AlignedScoresBelowMisaligned) {
  for (unsigned seed : {3u, 4u}) {
    const Pair p = simulatePair(seed);
    const UncertainCoralConfig cfg = planarConfig();
    const CoralResult aligned = computeCoralUncertain(p.a, transformScan(p.b, p.T_a_b), cfg);
    ASSERT_TRUE(aligned.valid);
    EXPECT_GT(aligned.overlap, 0.5);
    // Offsets applied in the later scan's sensor frame (DESIGN: induced misalignments).
    for (const Eigen::Isometry3d& err :
         {se2(0.5, 0, 0), se2(-0.5, 0, 0), se2(0, 0.5, 0), se2(0, -0.5, 0), se2(0, 0, 0.05)}) {
      const CoralResult mis = computeCoralUncertain(p.a, transformScan(p.b, p.T_a_b * err), cfg);
      ASSERT_TRUE(mis.valid);
      EXPECT_LT(aligned.quality, mis.quality)
          << "seed " << seed << " offset " << err.translation().transpose();
    }
  }
}

TEST(CoralUncertainty, ValidateNamesTheField) {
  UncertainCoralConfig cfg;
  cfg.gate_sigma = 0.0;
  EXPECT_NE(cfg.validate().find("gate_sigma"), std::string::npos);
  cfg = UncertainCoralConfig{};
  cfg.base.r_min = 2.0;
  cfg.base.r_max = 1.0;
  EXPECT_NE(cfg.validate().find("r_min"), std::string::npos);
}

// Oxford radar: RIP features with the Navtech polar covariances; Q at ground truth must be
// below Q with the later scan offset by 0.5 m in each direction, on every pair.
TEST(CoralUncertainty, OxfordGroundTruthBeatsHalfMetreOffsets) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  OxfordDataset ds;
  std::string err;
  ASSERT_TRUE(ds.load(coral_data, &err)) << err;
  ASSERT_GE(ds.png_paths.size(), 2u);
  // RIP features de-skewed by the online policy on the GT poses (the training path).
  OxfordTrainingConfig ocfg;
  ocfg.with_cfear = false;
  std::vector<TrainingScan> loaded;
  Isometries poses;
  ASSERT_TRUE(loadOxfordTrainingScans(ds, ocfg, nullptr, &loaded, &poses, &err)) << err;
  std::vector<Scan> scans;
  for (TrainingScan& t : loaded) {
    ASSERT_TRUE(attachCovariances(t.scan, RadarNoiseConfig::oxfordCts350x(), 2, &err)) << err;
    scans.push_back(t.scan);
  }
  UncertainCoralConfig cfg;
  cfg.base.dimension = 2;
  cfg.base.r_min = 0.75;
  cfg.base.r_max = 3.0;
  cfg.gate_sigma = 12.0;
  for (std::size_t i = 1; i < scans.size(); ++i) {
    const CoralResult gt =
        computeCoralUncertain(scans[i - 1], transformScan(scans[i], ds.T_prev_curr[i]), cfg);
    ASSERT_TRUE(gt.valid) << "pair " << i;
    for (const Eigen::Isometry3d& d :
         {se2(0.5, 0, 0), se2(-0.5, 0, 0), se2(0, 0.5, 0), se2(0, -0.5, 0)}) {
      const CoralResult off =
          computeCoralUncertain(scans[i - 1], transformScan(scans[i], ds.T_prev_curr[i] * d), cfg);
      EXPECT_LT(gt.quality, off.quality)
          << "pair " << i << " offset " << d.translation().transpose();
    }
  }
}
