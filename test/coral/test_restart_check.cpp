// The loop gate's restart check (coral/restart_check.hpp) and the registration behind it
// (coral/registration.hpp) on the planar synthetic yard pair, whose relative pose is known:
// registered from half a metre off, b comes back to the true pose; a candidate registered
// 1 m off is rejected and the check returns the true pose; the true pose stands (the restarts
// come back to it or end worse); through judgeAlignment the loop verdict rejects the 1 m
// candidate and offers the true pose; bad settings are refused. The loop gate's
// max_registered_offset (registeredNearby): a candidate a fraction of the tolerance off,
// rejected at its pose, is registered back to the true pose and accepted with it offered; one
// a full tolerance off is not. In 3D the check's coarse-to-fine registrations find what one
// registration with all points finds, and the coarse screen of the registration from the pose
// ends a candidate that runs away without changing one that comes back.
#include <gtest/gtest.h>

#include <algorithm>

#include "coral_introspection/coral/restart_check.hpp"
#include "coral_introspection/coral/verdict.hpp"
#include "coral_introspection/eval/loop_candidates.hpp"
#include "support/yard_pair.hpp"

namespace coral_introspection {
namespace {

using coral::se2;

// The restart check on `pair` at candidate pose T, with `judge` standing in for the loop
// verdict at T and at every pose the check judges.
coral::RestartResult restartCheck(const coral::CoralPair& pair, const coral::VerdictConfig& judge,
                                  const Eigen::Isometry3d& T, const coral::RestartConfig& cfg) {
  const coral::AlignmentVerdict v = coral::judgeAlignment(pair, T, judge);
  EXPECT_TRUE(v.valid);
  return coral::betterAlignmentElsewhere(
      pair, T, coral::judgedPose(v), judge.tolerance, cfg, [&](const Eigen::Isometry3d& pose) {
        return coral::judgedPose(coral::judgeAlignment(pair, pose, judge));
      });
}

struct YardCheck {
  test::YardPair p = test::yardPair(1);
  coral::CoralConfig coral = test::planarYardCoral();
  coral::VerdictConfig judge;
  std::unique_ptr<coral::CoralPair> pair;
  YardCheck() {
    judge.method = coral::VerdictMethod::kRelative;
    judge.tolerance = coral::ToleranceConfig::lidar2d();
    pair = coral::prepareVerdictPair(p.a, p.b, coral, judge);
  }
  // The check at candidate pose T; the stand-in for the loop verdict: the relative check.
  coral::RestartResult check(const Eigen::Isometry3d& T, const coral::RestartConfig& cfg = {}) {
    return restartCheck(*pair, judge, T, cfg);
  }
};

void expectNear(const Eigen::Isometry3d& T, const Eigen::Isometry3d& truth, double max_m,
                double max_deg) {
  double t = 0, deg = 0;
  eval::relativeError(T, truth, &t, &deg);
  EXPECT_LT(t, max_m);
  EXPECT_LT(deg, max_deg);
}

TEST(Registration, PointToLineComesBackToTheTruePose) {
  YardCheck s;
  const coral::SurfaceTarget target(s.pair->points(0), s.coral, coral::RegistrationConfig());
  EXPECT_GT(target.size(), 100u);
  for (const Eigen::Isometry3d& off :
       {se2(0.5, 0.0, 0.0), se2(-0.3, 0.4, 0.0), se2(0.0, 0.0, 0.1), se2(0.3, -0.3, -0.08)}) {
    const coral::RegistrationResult r = target.align(s.pair->points(1), s.p.T_a_b * off);
    EXPECT_TRUE(r.converged);
    EXPECT_GT(r.correspondences, 100);
    expectNear(r.T_a_b, s.p.T_a_b, 0.03, 0.3);  // [m, deg] a tenth of the tolerance
  }
}

// 3D (point-to-plane, 6 DoF): a 16-ring scan of the same yard, offsets in every axis. With
// CorAl's 0.3 m radius most neighbourhoods hold one ring: lines, which get no normal (a first
// version took their least direction and ended 7-15 cm off); 1 m spans two rings.
TEST(Registration, PointToPlaneComesBackToTheTruePoseIn3d) {
  const test::YardPair p = test::yardPair(16);
  coral::CoralConfig coral;  // 3D, r = 0.3 m
  const coral::CoralPair pair(p.a, p.b, coral);
  coral::RegistrationConfig reg;
  reg.normal_radius = 1.0;  // [m] patches spanning two of the 16 rings
  const coral::SurfaceTarget target(pair.points(0), coral, reg);
  EXPECT_GT(target.size(), 1000u);
  Eigen::Isometry3d tilt = coral::se2(0.2, -0.3, 0.05);
  tilt.translation().z() = 0.15;
  tilt.linear() = tilt.linear() * Eigen::AngleAxisd(0.03, Eigen::Vector3d::UnitX()).matrix() *
                  Eigen::AngleAxisd(-0.03, Eigen::Vector3d::UnitY()).matrix();
  for (const Eigen::Isometry3d& off : {se2(0.5, 0.0, 0.0), se2(0.0, 0.0, -0.1), tilt}) {
    const coral::RegistrationResult r = target.align(pair.points(1), p.T_a_b * off);
    EXPECT_TRUE(r.usable(reg));
    EXPECT_GT(r.correspondences, 500);
    expectNear(r.T_a_b, p.T_a_b, 0.03, 0.3);
  }
}

// align's stop: sees the pose after each update and ends the registration there.
TEST(Registration, StopEndsTheRegistrationAtThePoseItAccepts) {
  YardCheck s;
  const coral::SurfaceTarget target(s.pair->points(0), s.coral, coral::RegistrationConfig());
  const Eigen::Isometry3d from = s.p.T_a_b * se2(0.5, 0.0, 0.0);
  const coral::RegistrationResult full = target.align(s.pair->points(1), from);
  ASSERT_TRUE(full.converged);
  auto distance = [&](const Eigen::Isometry3d& T) {
    return (T.translation() - s.p.T_a_b.translation()).norm();
  };
  int calls = 0;
  const coral::RegistrationResult r =
      target.align(s.pair->points(1), from, coral::SurfaceTarget::kMaxSourcePoints, 0.0,
                   [&](const Eigen::Isometry3d& T) { return ++calls, distance(T) < 0.25; });
  EXPECT_TRUE(r.stopped);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(calls, r.iterations);
  EXPECT_LT(r.iterations, full.iterations);
  EXPECT_LT(distance(r.T_a_b), 0.25);  // where it stopped: on the way, not yet at the end
  EXPECT_GT(distance(r.T_a_b), distance(full.T_a_b));
  EXPECT_FALSE(full.stopped);
}

TEST(Registration, NoCorrespondencesIsNotConverged) {
  YardCheck s;
  const coral::SurfaceTarget target(s.pair->points(0), s.coral, coral::RegistrationConfig());
  // Every point of b 500 m away: nothing within max_correspondence.
  const coral::RegistrationResult r = target.align(s.pair->points(1), se2(500.0, 0.0, 0.0));
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.correspondences, 0);
  const coral::SurfaceTarget empty(coral::Points(), s.coral, coral::RegistrationConfig());
  EXPECT_EQ(empty.size(), 0u);
  EXPECT_FALSE(empty.align(s.pair->points(1), s.p.T_a_b).converged);
}

TEST(RestartCheck, ACandidateAMetreOffIsRejectedWithTheTruePose) {
  YardCheck s;
  for (const Eigen::Isometry3d& off : {se2(1.0, 0.0, 0.0), se2(0.0, -1.0, 0.05)}) {
    const coral::RestartResult r = s.check(s.p.T_a_b * off);
    EXPECT_TRUE(r.run);
    EXPECT_EQ(r.starts, 16);  // 2 radii x 8 directions
    ASSERT_TRUE(r.better_elsewhere);
    expectNear(r.T_a_b, s.p.T_a_b, 0.05, 0.5);  // the true pose, a sixth of the tolerance
    EXPECT_NEAR(r.distance, 1.0 / 0.3, 0.3);    // [tolerances] about 1 m from the candidate
    EXPECT_LT(r.q, 0.8 * r.q_candidate);
    EXPECT_LT(r.back, r.usable);  // some starts end at the true pose, not back here
  }
}

TEST(RestartCheck, TheTruePoseStands) {
  YardCheck s;
  const coral::RestartResult r = s.check(s.p.T_a_b);
  EXPECT_FALSE(r.better_elsewhere);
  EXPECT_GE(r.usable, 8);  // the registrations ran (and came back or ended worse)
  EXPECT_GE(r.back, 8);    // most back at the true pose (restart_back in coral_loop_eval's CSV)
  EXPECT_LE(r.back, r.usable);
  // The same with a Q margin of 0 (any lower Q counts) and starts nearer: still nothing.
  coral::RestartConfig near;
  near.radii = {1.0, 2.5};
  near.max_q_ratio = 1.0;
  EXPECT_FALSE(s.check(s.p.T_a_b, near).better_elsewhere);
}

// 3D (the 16-ring yard, 6 DoF): b has more points than RestartConfig::coarse_points, so each
// start is registered with those first (until it heads back within coarse_back_within) and
// again with all points only when it ends away from the candidate (and not where an earlier
// start's coarse registration ended). A candidate a metre off is rejected with the true pose,
// as by one registration with all points per start (coarse_points 0), and the true pose stands.
TEST(RestartCheck, CoarseToFineIn3dFindsWhatOneFullRegistrationFinds) {
  const test::YardPair p = test::yardPair(16);
  const coral::CoralConfig coral;  // 3D, r = 0.3 m
  // The stand-in for the loop verdict: Q and the overlap only (any p accepted), one CorAl
  // evaluation per pose; what the check compares.
  coral::VerdictConfig judge;
  judge.method = coral::VerdictMethod::kClassifier;
  judge.classifier.threshold = 0.0;
  judge.tolerance = coral::ToleranceConfig::lidar3d();
  const auto pair = coral::prepareVerdictPair(p.a, p.b, coral, judge);
  const auto check = [&](const Eigen::Isometry3d& T, const coral::RestartConfig& cfg) {
    return restartCheck(*pair, judge, T, cfg);
  };
  coral::RestartConfig coarse;
  coarse.registration.normal_radius = 1.0;  // [m] patches spanning two of the 16 rings
  ASSERT_GT(pair->points(1).size(), coarse.coarse_points);  // the coarse phase runs
  coral::RestartConfig full = coarse;
  full.coarse_points = 0;
  coral::RestartConfig each = coarse;  // coarse to fine, no start counted with another
  each.coarse_same_within = 0.0;
  for (const coral::RestartConfig* cfg : {&coarse, &full, &each}) {
    const coral::RestartResult r = check(p.T_a_b * se2(0.0, -1.0, 0.05), *cfg);
    EXPECT_EQ(r.starts, 16);
    ASSERT_TRUE(r.better_elsewhere);
    expectNear(r.T_a_b, p.T_a_b, 0.05, 0.5);
    EXPECT_NEAR(r.distance, 1.0 / 0.3, 0.3);  // [tolerances] about 1 m from the candidate
    // The starts that end away end at the true pose: all but the first are counted with it.
    if (cfg == &coarse)
      EXPECT_GE(r.merged, 3);
    else
      EXPECT_EQ(r.merged, 0);
  }
  const coral::RestartResult stands = check(p.T_a_b, coarse);
  EXPECT_FALSE(stands.better_elsewhere);
  EXPECT_GE(stands.usable, 8);
  // Coarse registrations that settle early (here: after one update, by a 1 m step bound) leave
  // the starts still farther than min_distance to the full registration, which is ended once
  // it comes back within coarse_back_within (4 of the 16 starts here): the true pose stands.
  coral::RestartConfig settles = coarse;
  settles.coarse_min_step = 1.0;
  settles.coarse_same_within = 0.0;
  const coral::RestartResult back = check(p.T_a_b, settles);
  EXPECT_FALSE(back.better_elsewhere);
  EXPECT_GT(back.returned, 0);
  EXPECT_EQ(back.usable, 16);
}

// Through the loop verdict (judgeAlignment, method gated with the loop gate's restarts).
TEST(RestartCheck, TheLoopVerdictRejectsTheMetreOffCandidateAndOffersTheTruePose) {
  YardCheck s;
  coral::VerdictConfig loop = s.judge;
  loop.method = coral::VerdictMethod::kGated;
  loop.gate.restarts = true;
  loop.classifier.threshold = 0.0;  // any p "aligned": the offer is decided by the restarts
  // On this clean yard the relative check sees the 1 m error at its default margin; loosened,
  // the candidate passes at its pose, as the relations registered off along the logs'
  // repeated structure do (doc/loop_closure.md).
  loop.relative.margin = 1.5;
  const Eigen::Isometry3d candidate = s.p.T_a_b * se2(1.0, 0.0, 0.0);
  const coral::AlignmentVerdict v = coral::judgeAlignment(*s.pair, candidate, loop);
  ASSERT_TRUE(v.valid);
  EXPECT_FALSE(v.aligned);
  EXPECT_TRUE(v.restart.better_elsewhere);
  EXPECT_NE(v.rejected_by.find("restarts:"), std::string::npos) << v.rejected_by;
  EXPECT_LE(v.probability, 0.5);  // "misaligned" reads as such whatever the local terms say
  ASSERT_TRUE(v.refined);
  expectNear(candidate * v.refinement.delta, s.p.T_a_b, 0.05, 0.5);
  // The true pose is accepted, the check ran and found nothing better.
  const coral::AlignmentVerdict t = coral::judgeAlignment(*s.pair, s.p.T_a_b, loop);
  EXPECT_TRUE(t.valid && t.aligned) << t.rejected_by;
  EXPECT_TRUE(t.restart.run);
  EXPECT_FALSE(t.refined);
  // Without restarts the 1 m candidate passes the relative check: what the check is for.
  loop.gate.restarts = false;
  const coral::AlignmentVerdict plain = coral::judgeAlignment(*s.pair, candidate, loop);
  EXPECT_TRUE(plain.valid && plain.aligned) << plain.rejected_by;
  EXPECT_FALSE(plain.restart.run);
}

TEST(NearbyAlignment, RegistersFromThePoseAndMeasuresHowFarItMoved) {
  YardCheck s;
  const coral::RestartConfig reg;  // its registration (and coarse screen: never reached here)
  int asked = 0;
  auto yes = [&](const Eigen::Isometry3d&) { return ++asked > 0; };
  // 0.12 m off (0.4 tolerances): registered back to the true pose, which is judged once.
  const Eigen::Isometry3d near = s.p.T_a_b * se2(0.12, 0.0, 0.0);
  coral::NearbyAlignment n =
      coral::registeredNearby(*s.pair, near, s.judge.tolerance, reg, 0.5, yes);
  EXPECT_TRUE(n.run && n.usable);
  EXPECT_TRUE(n.accepted);
  EXPECT_EQ(asked, 1);
  expectNear(n.T_a_b, s.p.T_a_b, 0.03, 0.3);
  EXPECT_NEAR(n.size, 0.4, 0.1);  // [tolerances] how far the registration moved it
  // The judge says no: not accepted, the registration is still reported.
  n = coral::registeredNearby(*s.pair, near, s.judge.tolerance, reg, 0.5,
                              [&](const Eigen::Isometry3d&) { return false; });
  EXPECT_TRUE(n.usable);
  EXPECT_FALSE(n.accepted);
  // A full tolerance off: the registration moves it about a tolerance, past the bound, and the
  // pose it reached is not even judged.
  asked = 0;
  n = coral::registeredNearby(*s.pair, s.p.T_a_b * se2(0.0, -0.3, 0.0), s.judge.tolerance, reg, 0.5,
                              yes);
  EXPECT_TRUE(n.usable);
  EXPECT_NEAR(n.size, 1.0, 0.1);
  EXPECT_FALSE(n.accepted);
  EXPECT_EQ(asked, 0);
  // Nothing to register onto: no pose, not accepted.
  n = coral::registeredNearby(*s.pair, se2(500.0, 0.0, 0.0), s.judge.tolerance, reg, 0.5, yes);
  EXPECT_FALSE(n.usable || n.accepted);
}

// 3D (the 16-ring yard): b has more points than coarse_points, so the registration from the
// pose is screened by the restart check's coarse phase. A candidate 0.12 m off passes the screen
// and is registered from its pose exactly as without the screen (coarse_points 0); one a metre
// off (3.3 tolerances) runs away from its pose, and the screen ends it a tolerance away,
// without judging: the full registration would also have ended past the bound (at the true
// pose).
TEST(NearbyAlignment, TheCoarseScreenEndsACandidateThatRunsAwayIn3d) {
  const test::YardPair p = test::yardPair(16);
  const coral::CoralConfig coral;  // 3D, r = 0.3 m
  coral::VerdictConfig judge;
  judge.tolerance = coral::ToleranceConfig::lidar3d();
  const auto pair = coral::prepareVerdictPair(p.a, p.b, coral, judge);
  coral::RestartConfig screened;
  screened.registration.normal_radius = 1.0;  // [m] patches spanning two of the 16 rings
  ASSERT_GT(pair->points(1).size(), screened.coarse_points);  // the screen runs
  coral::RestartConfig full = screened;
  full.coarse_points = 0;
  int asked = 0;
  auto yes = [&](const Eigen::Isometry3d&) { return ++asked > 0; };
  auto nearby = [&](const Eigen::Isometry3d& T, const coral::RestartConfig& cfg) {
    return coral::registeredNearby(*pair, T, judge.tolerance, cfg, 0.5, yes);
  };
  const Eigen::Isometry3d near = p.T_a_b * se2(0.12, 0.0, 0.0);
  const coral::NearbyAlignment a = nearby(near, screened), b = nearby(near, full);
  EXPECT_TRUE(a.accepted && b.accepted);
  EXPECT_FALSE(a.screened || b.screened);
  EXPECT_TRUE(a.T_a_b.isApprox(b.T_a_b, 1e-12));  // the same registration from the pose
  expectNear(a.T_a_b, p.T_a_b, 0.03, 0.3);
  EXPECT_EQ(asked, 2);
  asked = 0;
  const Eigen::Isometry3d off = p.T_a_b * se2(0.0, -1.0, 0.05);
  const coral::NearbyAlignment s = nearby(off, screened), f = nearby(off, full);
  EXPECT_TRUE(s.usable && s.screened);
  EXPECT_FALSE(s.accepted);
  EXPECT_GE(s.size, 1.0);  // stopped once a tolerance from the candidate
  EXPECT_LT(s.size, 2.0);  // and not much later
  EXPECT_FALSE(f.screened || f.accepted);
  EXPECT_TRUE(f.usable);
  EXPECT_NEAR(f.size, 1.0 / 0.3, 0.3);  // [tolerances] the full one: back at the true pose
  // A coarse phase that settles near the pose (here: after its first update, by a 1 m step
  // bound) leaves the screen to the full registration, which is stopped the same way.
  coral::RestartConfig settles = screened;
  settles.coarse_min_step = 1.0;
  const coral::NearbyAlignment l = nearby(off, settles);
  EXPECT_TRUE(l.usable && l.screened);
  EXPECT_GE(l.size, 1.0);
  EXPECT_LT(l.size, 2.0);
  EXPECT_EQ(asked, 0);
}

// Through the loop verdict: a candidate rejected at its pose (here by the gate's Q bound, set
// between Q at the true pose and Q at the candidate) and registered back within half a
// tolerance is accepted, the registered pose offered; a candidate a tolerance off stays
// rejected; with the bound at 0 nothing is registered.
TEST(NearbyAlignment, TheLoopVerdictAcceptsACandidateThatRegistersBackWithinTheBound) {
  YardCheck s;
  coral::VerdictConfig loop = s.judge;
  loop.method = coral::VerdictMethod::kGated;
  loop.classifier.threshold = 0.0;  // any p "aligned": decided by Q and the registration
  const Eigen::Isometry3d near = s.p.T_a_b * se2(0.0, 0.12, 0.0);
  const Eigen::Isometry3d far = s.p.T_a_b * se2(0.3, 0.0, 0.0);
  const double q_true = s.pair->evaluate(s.p.T_a_b).quality;
  const double q_near = s.pair->evaluate(near).quality;
  ASSERT_LT(q_true, q_near);
  loop.gate.max_quality = 0.5 * (q_true + q_near);
  coral::AlignmentVerdict v = coral::judgeAlignment(*s.pair, near, loop);
  ASSERT_TRUE(v.valid);
  EXPECT_FALSE(v.aligned);  // bound 0: rejected at its pose, nothing registered
  EXPECT_NE(v.rejected_by.find("gate: Q"), std::string::npos) << v.rejected_by;
  EXPECT_FALSE(v.nearby.run);
  loop.gate.max_registered_offset = 0.5;
  v = coral::judgeAlignment(*s.pair, near, loop);
  EXPECT_TRUE(v.valid && v.aligned) << v.rejected_by;
  EXPECT_TRUE(v.rejected_by.empty());
  EXPECT_TRUE(v.nearby.accepted);
  ASSERT_TRUE(v.refined);  // the registered pose is offered
  expectNear(near * v.refinement.delta, s.p.T_a_b, 0.03, 0.3);
  EXPECT_NEAR(v.refinement.size, 0.4, 0.1);
  EXPECT_LT(v.refinement.q_end, loop.gate.max_quality);
  // A tolerance off: registered back a tolerance, past the bound: rejected, nothing offered
  // by this term.
  const coral::AlignmentVerdict f = coral::judgeAlignment(*s.pair, far, loop);
  ASSERT_TRUE(f.valid);
  EXPECT_FALSE(f.aligned);
  EXPECT_TRUE(f.nearby.usable);
  EXPECT_GT(f.nearby.size, 0.5);
  EXPECT_FALSE(f.nearby.accepted);
  // The true pose is accepted at the pose: no registration.
  const coral::AlignmentVerdict t = coral::judgeAlignment(*s.pair, s.p.T_a_b, loop);
  EXPECT_TRUE(t.valid && t.aligned);
  EXPECT_FALSE(t.nearby.run);
  // The classifier's p at the registered pose must reach registered_min_probability (0 = the
  // verdict alone, lidar_3d; lidar_2d asks 0.5): just above it, rejected; at it, accepted.
  const double p_registered =
      coral::judgeAlignment(*s.pair, v.nearby.T_a_b, loop).classifier.probability;
  ASSERT_GT(p_registered, 0.0);
  ASSERT_LT(p_registered, 1.0);
  loop.gate.registered_min_probability = std::min(1.0, p_registered + 1e-6);
  const coral::AlignmentVerdict strict = coral::judgeAlignment(*s.pair, near, loop);
  EXPECT_FALSE(strict.aligned);
  EXPECT_TRUE(strict.nearby.usable);
  EXPECT_FALSE(strict.nearby.accepted);
  loop.gate.registered_min_probability = p_registered - 1e-6;
  EXPECT_TRUE(coral::judgeAlignment(*s.pair, near, loop).aligned);
  loop.gate.registered_min_probability = 1.5;
  EXPECT_NE(loop.validate().find("registered_min_probability"), std::string::npos);
}

TEST(RestartCheck, RefusesBadSettings) {
  EXPECT_EQ(coral::RestartConfig().validate(), "");
  auto refused = [](const coral::RestartConfig& c, const char* field) {
    const std::string e = c.validate();
    EXPECT_NE(e.find(field), std::string::npos) << e;
  };
  coral::RestartConfig c;
  c.radii = {};
  refused(c, "radii");
  c = coral::RestartConfig();
  c.radii = {2.0, -1.0};
  refused(c, "radii");
  c = coral::RestartConfig();
  c.directions = 0;
  refused(c, "directions");
  c = coral::RestartConfig();
  c.coarse_min_step = 0.0;
  refused(c, "coarse_min_step");
  c = coral::RestartConfig();
  c.coarse_back_within = c.min_distance + 0.1;  // would end starts the check counts as away
  refused(c, "coarse_back_within");
  c = coral::RestartConfig();
  c.coarse_same_within = c.coarse_back_within + 0.1;
  refused(c, "coarse_same_within");
  c.coarse_same_within = -0.1;
  refused(c, "coarse_same_within");
  c = coral::RestartConfig();
  c.max_q_ratio = 1.5;
  refused(c, "max_q_ratio");
  c = coral::RestartConfig();
  c.min_distance = 0.0;
  refused(c, "min_distance");
  c = coral::RestartConfig();
  c.registration.max_correspondence = -1.0;
  refused(c, "registration: max_correspondence");
  c = coral::RestartConfig();
  c.registration.max_iterations = 0;
  refused(c, "max_iterations");
  c = coral::RestartConfig();
  c.registration.normal_radius = -1.0;
  refused(c, "normal_radius");
  c = coral::RestartConfig();
  c.registration.robust_scale = -0.1;
  refused(c, "robust_scale");
  coral::VerdictConfig v;
  for (double bad : {-0.1, 1.0}) {  // a tolerance off registered back must stay rejected
    v.loop_closure.max_registered_offset = bad;
    EXPECT_NE(v.validate().find("loop_closure: max_registered_offset"), std::string::npos)
        << v.validate();
  }
  v.loop_closure.max_registered_offset = 0.99;
  EXPECT_EQ(v.validate(), "");
  v.restart.directions = 0;
  refused(v.restart, "directions");
  EXPECT_NE(v.validate().find("restart: directions"), std::string::npos) << v.validate();
}

}  // namespace
}  // namespace coral_introspection
