// CoralPair: CorAl of one pair at many poses with the pose-independent work done once. It
// must give computeCoral's result at every pose (the other cloud's neighbourhood is searched
// in its own frame and its moments rotated back: a wrong rotation or centre changes the
// joint entropies), and its probe sub-sample must be the same points at every pose.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "coral_introspection/coral/coral_pair.hpp"
#include "coral_introspection/eval/synthetic.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::eval;

namespace {

// Simulated 32-ring scans of the yard: a in the common frame, b in its own sensor frame,
// and the true T_a_b.
struct Pair {
  Scan a, b;
  Eigen::Isometry3d T_a_b;
};

Pair yardPair(unsigned seed) {
  std::mt19937 rng(seed);
  const SyntheticScene scene = SyntheticScene::structuredYard();
  const LidarModel lidar;
  const Eigen::Isometry3d T_w_a = se2(0, 0, 0), T_w_b = se2(0.8, 0.3, 0.25);
  Pair p;
  p.a.points = simulateScan(scene, T_w_a, lidar, rng);
  p.b.points = simulateScan(scene, T_w_b, lidar, rng);
  p.T_a_b = T_w_a.inverse() * T_w_b;
  return p;
}

// Poses around the truth that exercise every rotation axis (3D) and translations.
std::vector<Eigen::Isometry3d> posesNear(const Eigen::Isometry3d& T) {
  std::vector<Eigen::Isometry3d> out = {T, T * se2(0.4, -0.2, 0.05)};
  Eigen::Isometry3d tilt = Eigen::Isometry3d::Identity();
  tilt.linear() = Eigen::AngleAxisd(0.04, Eigen::Vector3d(1, 2, 0.5).normalized()).matrix();
  tilt.translation() = Eigen::Vector3d(0.1, 0.0, -0.15);
  out.push_back(T * tilt);
  return out;
}

void expectSameCoral(const CoralResult& pair, const CoralResult& ref) {
  ASSERT_EQ(pair.valid, ref.valid) << ref.reason;
  EXPECT_EQ(pair.num_queries, ref.num_queries);
  EXPECT_EQ(pair.num_overlap, ref.num_overlap);
  EXPECT_EQ(pair.num_valid, ref.num_valid);
  // Only the summation order of the neighbours' moments differs.
  EXPECT_NEAR(pair.h_joint, ref.h_joint, 1e-6);
  EXPECT_NEAR(pair.h_sep, ref.h_sep, 1e-6);
  EXPECT_NEAR(pair.quality, ref.quality, 1e-6);
}

}  // namespace

TEST(CoralPair, EqualsComputeCoralAtEveryPose3d) {
  const Pair p = yardPair(3);
  CoralConfig cfg;
  cfg.radius = 0.5;
  cfg.epsilon = 1e-8;
  cfg.merge_distance = 0.0;  // b filtered in its own frame would merge other points
  const CoralPair pair(p.a, p.b, cfg);
  for (const Eigen::Isometry3d& T : posesNear(p.T_a_b)) {
    SCOPED_TRACE(T.translation().transpose());
    expectSameCoral(pair.evaluate(T), computeCoral(p.a, transformScan(p.b, T), cfg));
  }
}

TEST(CoralPair, EqualsComputeCoralAtEveryPose2dDynamicRadius) {
  Pair p = yardPair(4);
  for (Scan* s : {&p.a, &p.b})
    for (Vec3& x : s->points) x.z() = 0.0;
  CoralConfig cfg = CoralConfig::radarPaper();
  cfg.dynamic_radius = true;  // radius from each point's own sensor: b.origin in b's frame
  cfg.r_min = 0.3;
  cfg.r_max = 0.9;
  cfg.alpha_deg = 3.0;
  p.b.origin = Vec3(0.0, 0.0, 0.0);
  const CoralPair pair(p.a, p.b, cfg);
  for (const Eigen::Isometry3d& T : {p.T_a_b, Eigen::Isometry3d(p.T_a_b * se2(-0.3, 0.5, -0.1))}) {
    expectSameCoral(pair.evaluate(T), computeCoral(p.a, transformScan(p.b, T), cfg));
  }
}

TEST(CoralPair, PerPointPositionsAreInTheCommonFrame) {
  const Pair p = yardPair(5);
  CoralConfig cfg;
  cfg.radius = 0.5;
  cfg.merge_distance = 0.0;
  const CoralResult r = CoralPair(p.a, p.b, cfg).evaluate(p.T_a_b);
  const Scan b_in_a = transformScan(p.b, p.T_a_b);
  ASSERT_EQ(r.per_point.size(), p.a.points.size() + p.b.points.size());
  Eigen::Vector3d sum[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  for (const PointEntropy& pe : r.per_point) sum[pe.scan] += pe.position.cast<double>();
  Eigen::Vector3d expect[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  for (const Vec3& x : p.a.points) expect[0] += x;
  for (const Vec3& x : b_in_a.points) expect[1] += x;
  for (int s = 0; s < 2; ++s)
    EXPECT_LT((sum[s] - expect[s]).norm() / static_cast<double>(r.per_point.size()), 1e-5) << s;
}

TEST(CoralPair, ProbeIsTheSameSubsetAtEveryPose) {
  const Pair p = yardPair(6);
  CoralConfig cfg;
  cfg.radius = 0.5;
  cfg.max_queries = 1500;
  const CoralPair pair(p.a, p.b, cfg, 200);
  for (const Eigen::Isometry3d& T : posesNear(p.T_a_b)) {
    CoralResult probe;
    const CoralResult all = pair.evaluate(T, &probe);
    const CoralResult alone = pair.evaluateProbe(T);
    EXPECT_EQ(all.num_queries, 3000u);
    EXPECT_EQ(probe.num_queries, 400u);
    // The probe of a full evaluation and a probe-only evaluation score the same points
    // with the same arithmetic: equal to the last bit.
    EXPECT_EQ(alone.num_queries, probe.num_queries);
    EXPECT_EQ(alone.quality, probe.quality);
    EXPECT_EQ(alone.h_joint, probe.h_joint);
    // A sub-sample estimate of the same mean: close to the full one, not equal.
    EXPECT_NEAR(probe.quality, all.quality, 4.0 * probe.quality_stderr + 1e-3);
    EXPECT_NE(probe.quality, all.quality);
  }
  // Without a probe count the probe is every query.
  const CoralPair whole(p.a, p.b, cfg, 0);
  CoralResult probe;
  const CoralResult all = whole.evaluate(p.T_a_b, &probe);
  EXPECT_EQ(probe.quality, all.quality);
  EXPECT_EQ(probe.num_queries, all.num_queries);
}

// Common random numbers: the probe's Q difference between the truth and a 0.3 m offset has
// the sign of the full difference, and Q is lower at the truth.
TEST(CoralPair, ProbeDifferencesFollowTheFullDifferences) {
  const Pair p = yardPair(7);
  CoralConfig cfg;
  cfg.radius = 0.5;
  cfg.max_queries = 2000;
  const CoralPair pair(p.a, p.b, cfg, 250);
  for (const Eigen::Isometry3d& d : {se2(0.3, 0, 0), se2(0, -0.3, 0), se2(0, 0, 0.035)}) {
    CoralResult probe0, probe1;
    const CoralResult full0 = pair.evaluate(p.T_a_b, &probe0);
    const CoralResult full1 = pair.evaluate(p.T_a_b * d, &probe1);
    EXPECT_GT(full1.quality, full0.quality);
    EXPECT_GT(probe1.quality, probe0.quality);
  }
}

TEST(CoralPair, RefusedOrEmptyInputGivesNoResult) {
  CoralConfig cfg;
  cfg.max_points = 10;
  cfg.refuse_over_max_points = true;
  Scan a, b;
  for (int i = 0; i < 20; ++i) a.points.emplace_back(0.1 * i, 0.0, 0.0);
  b = a;
  const CoralResult r = CoralPair(a, b, cfg, 5).evaluateProbe(Eigen::Isometry3d::Identity());
  EXPECT_FALSE(r.valid);
  EXPECT_NE(r.reason.find("refused"), std::string::npos) << r.reason;
  const CoralResult e = CoralPair(Scan(), Scan(), CoralConfig()).evaluate(se2(1, 2, 3));
  EXPECT_FALSE(e.valid);
  EXPECT_EQ(e.num_queries, 0u);
}
