// The gated verdict's coarse probe (coarse_probe.hpp, GateConfig::coarse_max_multiple and
// coarse_registration): its steps, and on a ray-cast planar pair the errors past the CorAl
// radius that the relative check and the classifier accept, rejected by it with the probe
// that points back to the truth; ground truth kept.
#include <gtest/gtest.h>

#include <cmath>

#include "coral_introspection/coral/types.hpp"
#include "coral_introspection/coral/verdict.hpp"
#include "support/yard_pair.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::test;

namespace {

VerdictConfig gated(int max_multiple, bool registration) {
  VerdictConfig v;
  v.tolerance = ToleranceConfig::lidar2d();  // 0.3 m, 5 deg
  v.method = VerdictMethod::kGated;
  v.gate.coarse_max_multiple = max_multiple;
  v.gate.coarse_registration = registration;
  return v;
}
}  // namespace

TEST(CoarseProbe, StepsTwoTolerancesApartThenTurn) {
  const ToleranceConfig tol = ToleranceConfig::lidar2d();
  EXPECT_TRUE(coarseOffsets(tol, 2, 0).empty());
  EXPECT_TRUE(coarseOffsets(tol, 2, 1).empty());
  const std::vector<ToleranceOffset> o = coarseOffsets(tol, 2, 10);
  ASSERT_EQ(o.size(), 5u * 6u + 3u);  // x, y, yaw both ways at 2, 4, 6, 8, 10 tolerances; turns
  EXPECT_EQ(o[0].name, "x+ x2");
  EXPECT_NEAR(o[0].delta.translation().x(), 0.6, 1e-12);
  EXPECT_EQ(o[9].name, "y- x4");
  EXPECT_NEAR(o[9].delta.translation().y(), -1.2, 1e-12);
  EXPECT_EQ(o[13].name, "x- x6");
  EXPECT_NEAR(o[13].delta.translation().x(), -1.8, 1e-12);
  EXPECT_EQ(o[16].name, "yaw+ x6");
  EXPECT_NEAR(yawOf(o[16].delta.linear()), 30.0 * M_PI / 180.0, 1e-12);
  EXPECT_EQ(o[29].name, "yaw- x10");
  EXPECT_NEAR(yawOf(o[29].delta.linear()), -50.0 * M_PI / 180.0, 1e-12);
  EXPECT_EQ(o[30].name, "yaw+ 90 deg");
  EXPECT_NEAR(yawOf(o[31].delta.linear()), -M_PI / 2, 1e-12);
  EXPECT_NEAR(std::abs(yawOf(o[32].delta.linear())), M_PI, 1e-12);
  // An odd largest multiple stops at the even one below; 3D has six axes.
  EXPECT_EQ(coarseOffsets(tol, 2, 9).size(), 4u * 6u + 3u);
  EXPECT_EQ(coarseOffsets(tol, 3, 3).size(), 12u + 3u);
}

// Two tolerances (0.6 m, past the 0.5 m radius) along x and y: the pose is a local minimum of
// Q for one-tolerance steps (the relative check and the classifier pass it), and the probe
// two tolerances back lands on the truth.
TEST(CoarseProbe, RejectsTwoTolerancesPastTheRadiusWithTheStepBack) {
  const YardPair p = yardPair(1);
  const CoralConfig coral = planarYardCoral();
  const AlignmentVerdict gt = judgeAlignment(p.a, p.b, p.T_a_b, coral, gated(10, true));
  ASSERT_TRUE(gt.valid);
  EXPECT_TRUE(gt.aligned) << gt.rejected_by;
  ASSERT_TRUE(gt.coarse.valid);
  EXPECT_LT(gt.coarse.drop(), 0.0);  // every probe, and the registration, higher than the truth
  EXPECT_LT(gt.coarse.registered_size, 0.5);  // registered from the truth: stays there
  struct Case {
    Eigen::Isometry3d delta;
    const char* back;
  };
  for (const Case& c : {Case{se2(0.6, 0, 0), "x- x2"}, Case{se2(-0.6, 0, 0), "x+ x2"},
                        Case{se2(0, 0.6, 0), "y- x2"}, Case{se2(0, -0.6, 0), "y+ x2"}}) {
    const Eigen::Isometry3d T = p.T_a_b * c.delta;
    const AlignmentVerdict off = judgeAlignment(p.a, p.b, T, coral, gated(0, false));
    ASSERT_TRUE(off.valid);
    EXPECT_TRUE(off.aligned) << c.back << ": without the probe the error passes";
    EXPECT_FALSE(off.coarse.valid);  // not measured when off
    const AlignmentVerdict v = judgeAlignment(p.a, p.b, T, coral, gated(10, false));
    ASSERT_TRUE(v.valid);
    EXPECT_FALSE(v.relative.misaligned) << c.back;
    EXPECT_FALSE(v.aligned) << c.back;
    EXPECT_EQ(v.coarse.lowest.name, c.back);
    EXPECT_FALSE(v.coarse.lowest_registered) << c.back;
    EXPECT_NE(v.rejected_by.find("past the CorAl radius"), std::string::npos) << v.rejected_by;
    EXPECT_NEAR(toleranceSize(v.coarse.lowest.delta, ToleranceConfig::lidar2d()), 2.0, 1e-9);
    EXPECT_GT(v.coarse.drop(), 0.05);
    EXPECT_NE(v.rejected_by.find("gate: coarse probe"), std::string::npos) << v.rejected_by;
    EXPECT_NE(v.rejected_by.find(c.back), std::string::npos) << v.rejected_by;
  }
}

// 2.5 tolerances (0.75 m) along x lies between the steps: the probes land half a tolerance
// from the truth, where Q is still high, and the error passes them; registered from the pose,
// b returns to the truth and the pose is rejected.
TEST(CoarseProbe, RegistrationFromThePoseCatchesAnErrorBetweenTheSteps) {
  const YardPair p = yardPair(1);
  const CoralConfig coral = planarYardCoral();
  const Eigen::Isometry3d T = p.T_a_b * se2(0.75, 0, 0);
  const AlignmentVerdict steps = judgeAlignment(p.a, p.b, T, coral, gated(10, false));
  ASSERT_TRUE(steps.valid);
  EXPECT_TRUE(steps.aligned) << steps.rejected_by;
  EXPECT_LT(steps.coarse.drop(), 0.0);
  const AlignmentVerdict v = judgeAlignment(p.a, p.b, T, coral, gated(10, true));
  ASSERT_TRUE(v.valid);
  EXPECT_FALSE(v.aligned);
  ASSERT_TRUE(v.coarse.registered);
  EXPECT_NEAR(v.coarse.registered_size, 2.5, 0.5);
  EXPECT_NEAR(toleranceSize(v.coarse.lowest.delta, ToleranceConfig::lidar2d()),
              v.coarse.registered_size, 1e-9);  // the lowest probe is the registered pose
  // The registered pose is the truth's, to a few centimetres.
  const Eigen::Isometry3d back = T * v.coarse.lowest.delta;
  EXPECT_LT((back.translation() - p.T_a_b.translation()).norm(), 0.05);
  EXPECT_NE(v.rejected_by.find("registered from it"), std::string::npos) << v.rejected_by;
  // Named as a lower minimum nearby, not as a step past the radius.
  EXPECT_TRUE(v.coarse.lowest_registered);
  EXPECT_NE(v.rejected_by.find("a lower minimum of Q nearby"), std::string::npos) << v.rejected_by;
  // A margin above the drop keeps the pose (the margin is what decides).
  VerdictConfig loose = gated(10, true);
  loose.gate.coarse_margin = v.coarse.drop() + 1e-9;
  EXPECT_TRUE(judgeAlignment(p.a, p.b, T, coral, loose).aligned);
}

// coarse_below_probability: the probe judges (and is run for) only poses whose classifier p is
// below it, a band above min_probability where p alone is unsure; above it the pose is the
// gate's p alone. The error of two tolerances above, judged with the band just below and just
// above its own p.
TEST(CoarseProbe, JudgesOnlyPosesBelowItsProbability) {
  const YardPair yard = yardPair(1);
  const auto judge = [&yard](const VerdictConfig& cfg) {  // two tolerances along x
    return judgeAlignment(yard.a, yard.b, yard.T_a_b * se2(0.6, 0, 0), planarYardCoral(), cfg);
  };
  VerdictConfig band = gated(10, false);
  const AlignmentVerdict every = judge(band);
  ASSERT_TRUE(every.valid && every.coarse.valid);
  ASSERT_FALSE(every.aligned);
  const double p_error = every.classifier.probability;
  ASSERT_GT(p_error, 1e-6);
  ASSERT_LT(p_error, 0.99);
  band.gate.coarse_below_probability = p_error * 1.01;  // p is in the band: judged, rejected
  const AlignmentVerdict in_band = judge(band);
  EXPECT_FALSE(in_band.aligned);
  EXPECT_NE(in_band.rejected_by.find("gate: coarse probe"), std::string::npos);
  band.gate.coarse_below_probability = p_error * 0.99;  // p above the band: not even run
  const AlignmentVerdict above = judge(band);
  EXPECT_TRUE(above.aligned) << above.rejected_by;
  EXPECT_FALSE(above.coarse.valid);
  band.measure_gate_terms = true;  // measured anyway (evaluation): still does not judge
  const AlignmentVerdict measured = judge(band);
  EXPECT_TRUE(measured.coarse.valid);
  EXPECT_TRUE(measured.aligned) << measured.rejected_by;
  EXPECT_TRUE(coarseProbeJudges(GateConfig(), 1.0));  // default 1: every pose, p = 1 too
}

TEST(CoarseProbe, ConfigOutOfRangeIsRefusedAndNamed) {
  VerdictConfig v = gated(10, true);
  EXPECT_EQ(v.validate(), "");
  for (int bad : {-1, 1, 17}) {
    v.gate.coarse_max_multiple = bad;
    EXPECT_NE(v.validate().find("coarse_max_multiple"), std::string::npos) << bad;
  }
  v.gate.coarse_max_multiple = 16;
  EXPECT_EQ(v.validate(), "");
  v.loop_closure.coarse_margin = -0.01;
  EXPECT_NE(v.validate().find("loop_closure"), std::string::npos);
  v.loop_closure.coarse_margin = std::nan("");
  EXPECT_NE(v.validate().find("coarse_margin"), std::string::npos);
  v.loop_closure.coarse_margin = 0.02;
  v.gate.min_probability = 0.01;
  for (double bad : {0.0, 0.01, 1.5, std::nan("")}) {  // at or below min_probability, above 1
    v.gate.coarse_below_probability = bad;
    EXPECT_NE(v.validate().find("coarse_below_probability"), std::string::npos) << bad;
  }
  v.gate.coarse_below_probability = 0.05;
  EXPECT_EQ(v.validate(), "");
}

// coarse_min_registered_offset: a registration measures an error to a fraction of the
// tolerance (Livox pairs moved by one tolerance come back 0.8-1.1 tolerances away). An error
// of exactly one tolerance between x and y with half the rotation tolerance passes the
// relative check on the yard pair, and the registration brings it back 0.9999 tolerances: with
// the bound at 1 that pose is not probed and the error is accepted; at 0.8 it is probed and
// rejected. The truth, which the registration leaves within a fraction of the tolerance, stays
// accepted.
TEST(CoarseProbe, RegisteredPoseProbedFromItsBound) {
  const YardPair p = yardPair(1);
  const CoralConfig coral = planarYardCoral();
  const double deg = 55.0 * M_PI / 180.0;
  const Eigen::Isometry3d delta = se2(0.3 * std::cos(deg), 0.3 * std::sin(deg), 2.5 * M_PI / 180);
  ASSERT_NEAR(toleranceSize(delta, ToleranceConfig::lidar2d()), 1.0, 1e-9);
  const Eigen::Isometry3d T = p.T_a_b * delta;
  const VerdictConfig at_one = gated(0, true);
  ASSERT_EQ(at_one.gate.coarse_min_registered_offset, 1.0);  // the default
  const AlignmentVerdict one = judgeAlignment(p.a, p.b, T, coral, at_one);
  ASSERT_TRUE(one.valid);
  EXPECT_FALSE(one.relative.misaligned);
  ASSERT_TRUE(one.coarse.registered);
  EXPECT_GT(one.coarse.registered_size, 0.95);
  EXPECT_LT(one.coarse.registered_size, 1.0);
  EXPECT_FALSE(one.coarse.lowest_registered);
  EXPECT_TRUE(one.aligned) << "the gap the bound closes: " << one.rejected_by;
  VerdictConfig below = gated(0, true);
  below.gate.coarse_min_registered_offset = 0.8;
  const AlignmentVerdict v = judgeAlignment(p.a, p.b, T, coral, below);
  ASSERT_TRUE(v.valid);
  EXPECT_FALSE(v.aligned);
  EXPECT_TRUE(v.coarse.lowest_registered);
  EXPECT_GT(v.coarse.drop(), 0.5);
  EXPECT_NE(v.rejected_by.find("registered from it"), std::string::npos) << v.rejected_by;
  const AlignmentVerdict gt = judgeAlignment(p.a, p.b, p.T_a_b, coral, below);
  EXPECT_TRUE(gt.valid && gt.aligned) << gt.rejected_by;
  EXPECT_LT(gt.coarse.registered_size, 0.5);
  for (double bad : {0.4, 2.5, std::nan("")}) {
    below.loop_closure.coarse_min_registered_offset = bad;
    EXPECT_NE(below.validate().find("coarse_min_registered_offset"), std::string::npos) << bad;
  }
}
