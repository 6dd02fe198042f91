// The second registration from several starts (eval/restart_check.hpp) on the planar
// synthetic yard pair, whose relative pose is known: a candidate registered 1 m off is
// rejected and the check returns the true pose; the true pose itself stands (the restarts come
// back to it or end worse); bad settings are refused.
#include <gtest/gtest.h>

#include "coral_introspection/eval/restart_check.hpp"
#include "support/yard_pair.hpp"

namespace coral_introspection {
namespace {

struct YardCheck {
  test::YardPair p = test::yardPair(1);
  coral::CoralConfig coral = test::planarYardCoral();
  coral::VerdictConfig judge;
  coral::ToleranceConfig tol = coral::ToleranceConfig::lidar2d();
  eval::LoopCandidateConfig reg = eval::evaluationCandidates(2, tol);
  std::unique_ptr<coral::CoralPair> pair;
  YardCheck() {
    judge.method = coral::VerdictMethod::kBoth;
    judge.tolerance = tol;
    reg.registration = "point_to_line";
    pair = coral::prepareVerdictPair(p.a, p.b, coral, judge);
  }
  // The check at candidate pose T; the stand-in for the loop verdict: the relative check.
  eval::RestartResult check(const Eigen::Isometry3d& T, const eval::RestartConfig& cfg = {}) {
    const coral::AlignmentVerdict v = coral::judgeAlignment(*pair, T, judge);
    EXPECT_TRUE(v.valid);
    return eval::betterAlignmentElsewhere(
        *pair, p.a.points, p.b.points, T, v, judge, reg,
        [](const coral::AlignmentVerdict& w) { return !w.relative.misaligned; }, cfg);
  }
};

TEST(RestartCheck, ACandidateAMetreOffIsRejectedWithTheTruePose) {
  YardCheck s;
  for (const Eigen::Isometry3d& off : {coral::se2(1.0, 0.0, 0.0), coral::se2(0.0, -1.0, 0.05)}) {
    const eval::RestartResult r = s.check(s.p.T_a_b * off);
    EXPECT_EQ(r.starts, 16);  // 2 radii x 8 directions
    ASSERT_TRUE(r.better_elsewhere);
    double t = 0, deg = 0;
    eval::relativeError(r.T_a_b, s.p.T_a_b, &t, &deg);
    EXPECT_LT(t, 0.05);  // [m] the true pose, a sixth of the tolerance
    EXPECT_LT(deg, 0.5);
    EXPECT_NEAR(r.distance, 1.0 / 0.3, 0.3);  // [tolerances] about 1 m from the candidate
    EXPECT_LT(r.q, 0.8 * r.q_candidate);
  }
}

TEST(RestartCheck, TheTruePoseStands) {
  YardCheck s;
  const eval::RestartResult r = s.check(s.p.T_a_b);
  EXPECT_FALSE(r.better_elsewhere);
  EXPECT_GE(r.converged, 8);  // the registrations ran (and came back or ended worse)
  // The same with a Q margin of 0 (any lower Q counts) and starts nearer: still nothing.
  eval::RestartConfig near;
  near.radii = {1.0, 2.5};
  near.max_q_ratio = 1.0;
  EXPECT_FALSE(s.check(s.p.T_a_b, near).better_elsewhere);
}

TEST(RestartCheck, RefusesBadSettings) {
  EXPECT_EQ(eval::RestartConfig().validate(), "");
  eval::RestartConfig c;
  c.radii = {};
  EXPECT_NE(c.validate().find("radii"), std::string::npos);
  c = eval::RestartConfig();
  c.radii = {2.0, -1.0};
  EXPECT_NE(c.validate().find("radii"), std::string::npos);
  c = eval::RestartConfig();
  c.directions = 0;
  EXPECT_NE(c.validate().find("directions"), std::string::npos);
  c = eval::RestartConfig();
  c.max_q_ratio = 1.5;
  EXPECT_NE(c.validate().find("max_q_ratio"), std::string::npos);
  c = eval::RestartConfig();
  c.min_distance = 0.0;
  EXPECT_NE(c.validate().find("min_distance"), std::string::npos);
}

}  // namespace
}  // namespace coral_introspection
