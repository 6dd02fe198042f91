// The stream verdict as the scan-matching front ends use it (ros_eval::streamVerdictDecision):
// a step the verdict rejects because its registration reached a lower minimum of Q is taken at
// that minimum when the verdict accepts it there; any other rejection leaves the step refused.
#include <gtest/gtest.h>

#include "coral_introspection/coral/tolerance.hpp"
#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/ros_eval/stream_decision.hpp"
#include "support/yard_pair.hpp"

namespace {

using coral_introspection::coral::se2;
using coral_introspection::coral::ToleranceConfig;
using coral_introspection::coral::toleranceSize;
namespace eval = coral_introspection::eval;
namespace online = coral_introspection::online;
namespace test = coral_introspection::test;

// The yard pair's planar scans as two keyframes, judged by the gated verdict with the coarse
// probe's registration (no fixed steps) at the 2D tolerance (0.3 m, 5 deg).
struct Keyframes {
  test::YardPair pair = test::yardPair(1);
  std::vector<eval::TrainingScan> scans;
  online::IntrospectorConfig cfg;
  Keyframes() {
    scans.resize(2);
    scans[0].scan = pair.a;
    scans[1].scan = pair.b;
    cfg.coral = test::planarYardCoral();
    cfg.verdict.tolerance = ToleranceConfig::lidar2d();
    cfg.verdict.method = coral_introspection::coral::VerdictMethod::kGated;
    cfg.verdict.gate.coarse_registration = true;
  }
  // The step from 0 to 1 at truth * delta, as a front end's registration handed it over.
  eval::LoopCandidate step(const Eigen::Isometry3d& delta) const {
    eval::LoopCandidate c;
    c.a = 0;
    c.b = 1;
    c.T_a_b = pair.T_a_b * delta;
    return c;
  }
  double offTolerances(const Eigen::Isometry3d& T) const {
    return toleranceSize(pair.T_a_b.inverse() * T, cfg.verdict.tolerance);
  }
};

// 0.75 m along x (2.5 tolerances) passes the relative check; the registration from it reaches
// the truth (test_coarse_probe), so the verdict rejects it and the front end keeps the step at
// the pose the registration reached, within half a tolerance of the truth.
TEST(StreamDecision, AStepShortOfTheMinimumIsTakenWhereTheRegistrationReached) {
  const Keyframes k;
  const eval::LoopCandidate c = k.step(se2(0.75, 0, 0));
  const online::PairJudgement at_step =
      online::judgePair(k.scans[0].scan, k.scans[1].scan, c.T_a_b, k.cfg, false);
  ASSERT_TRUE(at_step.verdict.valid);
  ASSERT_FALSE(at_step.verdict.aligned);
  ASSERT_TRUE(at_step.verdict.coarse.lowest_registered) << at_step.verdict.rejected_by;
  Eigen::Isometry3d T = c.T_a_b;
  EXPECT_TRUE(coral_introspection::ros_eval::streamVerdictDecision(k.scans, k.cfg)(c, &T));
  EXPECT_NEAR(k.offTolerances(c.T_a_b), 2.5, 1e-9);
  EXPECT_LT(k.offTolerances(T), 0.5);
  // The truth itself is accepted as it is.
  const eval::LoopCandidate truth = k.step(Eigen::Isometry3d::Identity());
  T = truth.T_a_b;
  EXPECT_TRUE(coral_introspection::ros_eval::streamVerdictDecision(k.scans, k.cfg)(truth, &T));
  EXPECT_LT(k.offTolerances(T), 1e-12);
}

// The same step's verdict where the shared structure is a corridor's to the gate (its
// constraint term below the bound): a lower Q along a corridor is no evidence, and the step is
// not moved along it. Without the constraint measured, or at its bound, it is.
TEST(StreamDecision, ACorridorsStepIsNotMovedAlongIt) {
  Keyframes k;
  const online::PairJudgement j = online::judgePair(k.scans[0].scan, k.scans[1].scan,
                                                    k.step(se2(0.75, 0, 0)).T_a_b, k.cfg, false);
  EXPECT_TRUE(coral_introspection::ros_eval::lowerMinimumNearby(j.verdict, k.cfg.verdict));
  k.cfg.verdict.gate.min_constraint = 0.04;
  coral_introspection::coral::AlignmentVerdict v = j.verdict;
  v.constraint.valid = true;
  v.constraint.weakest = 0.04;
  EXPECT_TRUE(coral_introspection::ros_eval::lowerMinimumNearby(v, k.cfg.verdict));
  v.constraint.weakest = 0.02;
  EXPECT_FALSE(coral_introspection::ros_eval::lowerMinimumNearby(v, k.cfg.verdict));
}

// Rejected by another term (the relative check, one tolerance along x): refused, unmoved.
TEST(StreamDecision, OtherRejectionsLeaveTheStepRefused) {
  const Keyframes k;
  for (const Eigen::Isometry3d& delta : {se2(0.3, 0, 0), se2(-0.3, 0, 0)}) {
    const eval::LoopCandidate c = k.step(delta);
    const online::PairJudgement j =
        online::judgePair(k.scans[0].scan, k.scans[1].scan, c.T_a_b, k.cfg, false);
    ASSERT_TRUE(j.verdict.valid);
    EXPECT_TRUE(j.verdict.relative.misaligned) << j.verdict.rejected_by;
    EXPECT_FALSE(coral_introspection::ros_eval::lowerMinimumNearby(j.verdict, k.cfg.verdict));
    Eigen::Isometry3d T = c.T_a_b;
    EXPECT_FALSE(coral_introspection::ros_eval::streamVerdictDecision(k.scans, k.cfg)(c, &T));
    EXPECT_TRUE(T.isApprox(c.T_a_b));
  }
}

}  // namespace
