// The loop gate's refinement (coral/refinement.hpp, GateConfig::max_refinement) on a 2D room
// whose true relative pose is known: from a pose a fraction of the tolerance off, the walk on
// Q ends near the truth; it never goes further than the bound; the loop verdict rejects such
// a pose (it is the given pose's verdict) and offers the refined pose, which passes; from
// several tolerances off nothing is offered when the refined pose fails the gate.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "coral_introspection/coral/refinement.hpp"
#include "coral_introspection/coral/verdict.hpp"

using namespace coral_introspection::coral;

namespace {

// Points every `step` from (x0, y0) to (x1, y1), starting `phase` of a step in, z = 0.
void wall(double x0, double y0, double x1, double y1, double step, double phase, Points* out) {
  const Vec3 p(x0, y0, 0.0), q(x1, y1, 0.0);
  const double len = (q - p).norm();
  for (double s = phase * step; s <= len; s += step) out->push_back(p + (q - p) * (s / len));
}

// An L-shaped room with a pillar: no symmetry, every direction pinned. Scans sample it with
// different phases, as two real scans never hit the same spots.
Points room(double phase) {
  Points pts;
  const double st = 0.05;
  wall(0, 0, 8, 0, st, phase, &pts);
  wall(8, 0, 8, 4, st, phase, &pts);
  wall(8, 4, 3, 4, st, phase, &pts);
  wall(3, 4, 3, 7, st, phase, &pts);
  wall(3, 7, 0, 7, st, phase, &pts);
  wall(0, 7, 0, 0, st, phase, &pts);
  wall(5, 1.5, 6, 1.5, st, phase, &pts);  // pillar
  wall(6, 1.5, 6, 2.5, st, phase, &pts);
  wall(6, 2.5, 5, 2.5, st, phase, &pts);
  wall(5, 2.5, 5, 1.5, st, phase, &pts);
  return pts;
}

struct Pair {
  Scan a, b;
  Eigen::Isometry3d truth;  // T_a_b
};

Pair roomPair() {
  Pair p;
  p.a.points = room(0.0);
  p.truth = se2(1.2, 0.8, 0.3);  // b's sensor in a's frame
  for (const Vec3& q : room(0.5)) p.b.points.push_back(p.truth.inverse() * q);
  p.a.origin = Vec3(2.0, 2.0, 0.0);
  p.b.origin = p.truth.inverse() * Vec3(2.5, 2.0, 0.0);
  return p;
}

CoralConfig planar() {
  CoralConfig c;
  c.dimension = 2;
  c.radius = 0.5;
  c.epsilon = 1e-4;
  return c;
}

// How far pose T is from the truth, in tolerances.
double offTruth(const Eigen::Isometry3d& T, const Pair& p, const ToleranceConfig& tol) {
  return toleranceSize(p.truth.inverse() * T, tol);
}

VerdictConfig loopGate(double max_refinement) {
  VerdictConfig v;
  v.method = VerdictMethod::kGated;
  v.tolerance = ToleranceConfig::lidar2d();  // 0.3 m, 5 deg
  v.gate.max_refinement = max_refinement;
  return v;
}

}  // namespace

TEST(Refinement, ToleranceSizeIsTheLargerShare) {
  const ToleranceConfig tol = ToleranceConfig::lidar2d();
  EXPECT_NEAR(toleranceSize(se2(0.15, 0.0, 0.0), tol), 0.5, 1e-12);
  EXPECT_NEAR(toleranceSize(se2(0.0, 0.0, 10.0 * M_PI / 180.0), tol), 2.0, 1e-9);
  EXPECT_NEAR(toleranceSize(se2(0.18, 0.24, 2.5 * M_PI / 180.0), tol), 1.0, 1e-9);  // |t| 0.3
}

TEST(Refinement, WalkFromAFractionOfTheToleranceEndsNearTheTruth) {
  const Pair p = roomPair();
  const ToleranceConfig tol = ToleranceConfig::lidar2d();
  const CoralPair pair(p.a, p.b, planar());
  for (const Eigen::Isometry3d& off :
       {se2(0.2, 0.0, 0.0), se2(0.0, -0.2, 0.0), se2(0.12, 0.12, 3.0 * M_PI / 180.0)}) {
    const Eigen::Isometry3d start = p.truth * off;
    const PoseRefinement r = refinePose(pair, start, 2, tol, 1.0);
    ASSERT_TRUE(r.valid);
    EXPECT_GT(r.size, 0.0);
    EXPECT_LE(r.size, 1.0 + 1e-9);
    EXPECT_LT(r.q_end, r.q_start);
    const double before = offTruth(start, p, tol), after = offTruth(start * r.delta, p, tol);
    EXPECT_LT(after, 0.3) << "from " << before << " tolerances off";
    EXPECT_LT(after, 0.5 * before);
  }
}

TEST(Refinement, NeverWalksPastTheBoundAndZeroIsOff) {
  const Pair p = roomPair();
  const ToleranceConfig tol = ToleranceConfig::lidar2d();
  const CoralPair pair(p.a, p.b, planar());
  // 1.8 tolerances off, 0.54 m: past the CorAl radius (0.5 m) Q no longer points at the
  // truth, so where the walk ends is not asserted, only that it stays within the bound.
  const Eigen::Isometry3d start = p.truth * se2(0.45, -0.3, 0.0);
  for (double bound : {0.25, 0.5, 1.0}) {
    const PoseRefinement r = refinePose(pair, start, 2, tol, bound);
    EXPECT_GT(r.size, 0.0);
    EXPECT_LE(r.size, bound + 1e-9);
    EXPECT_LT(r.q_end, r.q_start);
  }
  const PoseRefinement none = refinePose(pair, start, 2, tol, 0.0);
  EXPECT_EQ(none.size, 0.0);
  EXPECT_TRUE(none.delta.isApprox(Eigen::Isometry3d::Identity()));
  // At the truth there is nothing lower to walk to.
  EXPECT_LT(refinePose(pair, p.truth, 2, tol, 1.0).size, 0.3);
}

TEST(Refinement, LoopVerdictOffersTheRefinedPoseAndStaysTheGivenPoses) {
  const Pair p = roomPair();
  const Eigen::Isometry3d start = p.truth * se2(0.2, 0.0, 0.0);  // within the tolerance
  const AlignmentVerdict plain = judgeAlignment(p.a, p.b, start, planar(), loopGate(0.0));
  ASSERT_TRUE(plain.valid) << plain.reason;
  // Q one tolerance towards the truth (0.1 m past it) is lower: rejected at the pose.
  ASSERT_FALSE(plain.aligned);
  EXPECT_FALSE(plain.refined);
  const AlignmentVerdict v = judgeAlignment(p.a, p.b, start, planar(), loopGate(1.0));
  ASSERT_TRUE(v.valid) << v.reason;
  EXPECT_FALSE(v.aligned);  // the given pose's verdict, refinement or not
  EXPECT_EQ(v.coral.quality, plain.coral.quality);
  EXPECT_TRUE(v.refined);  // the refined pose passes: offered
  EXPECT_GT(v.refinement.size, 0.0);
  EXPECT_LT(v.refinement.q_end, v.refinement.q_start);
  EXPECT_LT(offTruth(start * v.refinement.delta, p, loopGate(1.0).tolerance), 0.3);
  EXPECT_NE(v.rejected_by.find("passes (transform_a_b * correction)"), std::string::npos)
      << v.rejected_by;
  // The stream's gated verdict never refines (max_refinement is the loop gate's).
  VerdictConfig stream = loopGate(1.0);
  stream.method = VerdictMethod::kRelative;
  EXPECT_FALSE(judgeAlignment(p.a, p.b, start, planar(), stream).refined);
}

// 3 tolerances off (0.9 m, past the CorAl radius) the walk ends at another local minimum of
// Q, which the relative check alone accepts (measured: 3.2 tolerances from the truth): what
// keeps such a pose out is the gate's absolute terms, as for a false loop candidate that ICP
// converged on. Here the overlap (1.0 at the truth, 0.54 there): with it the refined pose is
// rejected too, and the rejection says both.
TEST(Refinement, PoseSeveralTolerancesOffStaysRejectedByTheGate) {
  const Pair p = roomPair();
  const Eigen::Isometry3d start = p.truth * se2(0.9, 0.0, 0.0);
  VerdictConfig gate = loopGate(1.0);
  gate.gate.min_overlap = 0.8;
  const AlignmentVerdict at_truth = judgeAlignment(p.a, p.b, p.truth, planar(), gate);
  EXPECT_TRUE(at_truth.valid && at_truth.aligned) << at_truth.rejected_by;
  const AlignmentVerdict v = judgeAlignment(p.a, p.b, start, planar(), gate);
  ASSERT_TRUE(v.valid) << v.reason;
  EXPECT_FALSE(v.aligned);
  EXPECT_FALSE(v.refined);
  EXPECT_GT(v.refinement.size, 0.0);  // it walked, and the refined pose was rejected too
  EXPECT_GE(offTruth(start * v.refinement.delta, p, gate.tolerance), 2.0);
  EXPECT_NE(v.rejected_by.find("at the pose refined by"), std::string::npos) << v.rejected_by;
  EXPECT_NE(v.rejected_by.find("overlap"), std::string::npos) << v.rejected_by;
}

TEST(Refinement, BoundIsValidated) {
  GateConfig g;
  g.max_refinement = 1.5;  // beyond the tolerance: the verdict would mean something else
  EXPECT_NE(g.validate().find("max_refinement"), std::string::npos);
  g.max_refinement = -0.1;
  EXPECT_NE(g.validate().find("max_refinement"), std::string::npos);
  g.max_refinement = 1.0;
  EXPECT_EQ(g.validate(), "");
}
