// online::Introspector without a ROS master: lidar and radar streams through the synthetic
// yard with ground-truth poses, pose errors, a looping bag, gaps, TF failures, duplicate
// stamps, keyframe pairing and the Doppler check with point covariances.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include "coral_introspection/eval/doppler_simulation.hpp"
#include "coral_introspection/eval/synthetic.hpp"
#include "coral_introspection/online/introspector.hpp"

using namespace coral_introspection;
using coral::Vec3;
using online::PairAction;

namespace {

// Sensor pose at time t [s]: 8 m/s forward while turning at 0.8 rad/s (fast for a spinning
// radar: a revolution of 0.25 s is distorted by up to 2 m).
Eigen::Isometry3d drivePose(double t) {
  radar::Twist v;
  v.linear = Vec3(8.0, 0.0, 0.0);
  v.angular = Vec3(0.0, 0.0, 0.8);
  return coral::se2(-6.0, -2.0, 0.2) * radar::constantVelocityPose(v, t);
}

// One revolution of a spinning radar starting at t0: azimuth i is measured at
// t0 + i * period / n from the pose at that time; points in that (moving) sensor frame.
radar::RadarFeatures radarScan(double t0, std::mt19937& rng, int n = 720, double period = 0.25) {
  const auto scene = eval::SyntheticScene::structuredYard();
  std::normal_distribution<double> noise(0.0, 0.03);
  radar::RadarFeatures f;
  for (int i = 0; i < n; ++i) {
    const double t = t0 + period * i / n, az = 2.0 * M_PI * i / n;
    const Eigen::Isometry3d T = drivePose(t);
    const Vec3 d(std::cos(az), std::sin(az), 0.0);
    const auto r = scene.castRay(T.translation(), T.linear() * d, 40.0);
    if (!r || *r < 2.5) continue;
    f.points.push_back((*r + noise(rng)) * d);
    f.stamps.push_back(t);
    f.intensity.push_back(100.f);
  }
  return f;
}

online::ScanInput radarInput(double t0, std::mt19937& rng, const Eigen::Isometry3d& pose) {
  online::ScanInput in;
  in.stamp = t0;
  in.id = static_cast<uint64_t>(std::llround(t0 * 1e9));
  in.features = radarScan(t0, rng);
  in.is_radar = true;
  in.T_fixed_sensor = pose;
  return in;
}

online::IntrospectorConfig radarConfig() {
  online::IntrospectorConfig c;
  c.coral = coral::CoralConfig::radarPaper();  // 2D, r = 1 m
  c.verdict.classifier.beta0 = 11.0;           // boundary Q = 0.55 nats (radar preset)
  c.verdict.classifier.beta1 = -20.0;
  c.verdict.classifier.beta2 = 20.0;
  return c;
}

online::ScanInput lidarInput(double stamp, const Eigen::Isometry3d& truth,
                             const Eigen::Isometry3d& reported, std::mt19937& rng) {
  eval::LidarModel m;
  m.rings = 16;
  online::ScanInput in;
  in.stamp = stamp;
  in.features.points = eval::simulateScan(eval::SyntheticScene::structuredYard(), truth, m, rng);
  in.T_fixed_sensor = reported;
  return in;
}

online::IntrospectorConfig lidarConfig() {
  online::IntrospectorConfig c;  // the lidar_3d preset's CorAl and classifier
  c.coral.radius = 1.0;
  c.coral.epsilon = 1e-4;
  c.verdict.classifier.beta0 = 4.0;  // boundary Q = 0.2 nats
  c.verdict.classifier.beta1 = -20.0;
  c.verdict.classifier.beta2 = 20.0;
  return c;
}

// A tiny lidar scan: enough for pairing / reset logic, no CorAl verdict needed.
online::ScanInput tinyInput(double stamp, const Vec3& position) {
  online::ScanInput in;
  in.stamp = stamp;
  in.features.points = {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  in.T_fixed_sensor = Eigen::Isometry3d(Eigen::Translation3d(position));
  return in;
}

}  // namespace

TEST(Introspector, LidarPoseErrorFlagsExactlyThePairsUsingIt) {
  online::Introspector intro(lidarConfig());
  std::mt19937 rng(5);
  const int bad = 3;
  for (int k = 0; k < 6; ++k) {
    const double t = 0.1 * k;
    const Eigen::Isometry3d truth = coral::se2(-8.0 + 0.5 * k, -1.0, 0.05 * k);
    Eigen::Isometry3d reported = truth;
    if (k == bad) reported = truth * Eigen::Translation3d(0.0, 0.5, 0.0);  // odometry error
    const online::Report r = intro.process(lidarInput(t, truth, reported, rng));
    ASSERT_TRUE(r.has_pose);
    if (k == 0) {
      EXPECT_EQ(r.action, PairAction::kFirst);
      EXPECT_FALSE(r.judged);
      EXPECT_NE(r.reason.find("first scan"), std::string::npos) << r.reason;
      continue;
    }
    ASSERT_TRUE(r.hasVerdict()) << "pair " << k - 1 << "-" << k << ": " << r.reason;
    EXPECT_TRUE(r.reason.empty());
    EXPECT_DOUBLE_EQ(r.stamp_ref, 0.1 * (k - 1));
    const bool uses_bad = k == bad || k == bad + 1;
    EXPECT_EQ(r.pair.verdict.aligned, !uses_bad)
        << "pair " << k - 1 << "-" << k << " Q = " << r.pair.verdict.coral.quality;
  }
  EXPECT_EQ(intro.counters().pairs, 5u);
  EXPECT_EQ(intro.counters().valid_pairs, 5u);
  EXPECT_EQ(intro.counters().misaligned, 2u);
}

TEST(Introspector, RadarDeskewMakesTheMovingScansConsistent) {
  // Same scans with and without de-skewing: at 8 m/s and 0.8 rad/s the raw revolutions do
  // not overlap well even with exact poses; de-skewed they do.
  double q_deskew = 0.0, q_raw = 0.0;
  for (bool deskew : {true, false}) {
    online::IntrospectorConfig c = radarConfig();
    c.deskew.enabled = deskew;
    online::Introspector intro(c);
    std::mt19937 rng(2);
    int judged = 0;
    for (int k = 0; k < 5; ++k) {
      const double t0 = 50.0 + 0.25 * k;
      const online::Report r = intro.process(radarInput(t0, rng, drivePose(t0 - 50.0)));
      EXPECT_EQ(r.deskewed, deskew && k > 0) << k;
      if (!r.judged) continue;
      ASSERT_TRUE(r.pair.verdict.coral.valid) << r.reason;
      ++judged;
      (deskew ? q_deskew : q_raw) += r.pair.verdict.coral.quality / 4.0;
      if (deskew) {
        EXPECT_TRUE(r.pair.verdict.aligned)
            << "pair " << k << " Q = " << r.pair.verdict.coral.quality;
      }
    }
    EXPECT_EQ(judged, 4);
  }
  std::printf("mean Q over 4 pairs: de-skewed %.3f, raw %.3f\n", q_deskew, q_raw);
  EXPECT_GT(q_raw, 0.1);             // the distortion is visible to CorAl ...
  EXPECT_LT(3.0 * q_deskew, q_raw);  // ... and the de-skewed pairs are far more consistent
}

// A slow 2D laser on a turning robot: 360 beams over 0.1 s (a 10 Hz scanner) while the robot
// drives at 0.5 m/s and turns at 1.5 rad/s, so a sweep turns 8.6 deg. The same beams with their
// times (a LaserScan's time_increment: point_stamps) are de-skewed with the poses' velocity and
// then overlap; without the times, or with motion_compensation off, they do not.
TEST(Introspector, LaserBeamsWithTimesAreDeskewed) {
  auto pose = [](double t) {
    radar::Twist v;
    v.linear = Vec3(0.5, 0.0, 0.0);
    v.angular = Vec3(0.0, 0.0, 1.5);
    return coral::se2(-4.0, -1.0, 0.3) * radar::constantVelocityPose(v, t);
  };
  const auto scene = eval::SyntheticScene::structuredYard();
  auto sweep = [&](double t0, bool stamped) {
    online::ScanInput in;
    in.stamp = t0;
    in.id = static_cast<uint64_t>(std::llround(t0 * 1e3));
    for (int i = 0; i < 360; ++i) {
      const double t = t0 + 0.1 * i / 360.0, az = 2.0 * M_PI * i / 360.0;
      const Eigen::Isometry3d T = pose(t);
      const Vec3 d(std::cos(az), std::sin(az), 0.0);
      const auto r = scene.castRay(T.translation(), T.linear() * d, 30.0);
      if (!r) continue;
      in.features.points.push_back(*r * d);
      if (stamped) in.features.stamps.push_back(t);
    }
    in.point_stamps = stamped;
    in.T_fixed_sensor = pose(t0);
    return in;
  };
  online::IntrospectorConfig c;
  c.coral.dimension = 2;
  c.coral.radius = 0.5;
  c.coral.epsilon = 1e-4;
  online::ProcessOptions keep;
  keep.keep_features = true;
  double q[3] = {0.0, 0.0, 0.0};  // de-skewed; times but motion_compensation off; no times
  for (int run = 0; run < 3; ++run) {
    c.deskew.enabled = run != 1;
    online::Introspector intro(c);
    for (int k = 0; k < 4; ++k) {
      const double t0 = 0.1 * k;
      const online::ScanInput in = sweep(t0, run != 2);
      const online::Report r = intro.process(in, keep);
      EXPECT_EQ(r.deskewed, run == 0 && k > 0) << run << " " << k;
      // Known answer: de-skewed, each beam's point is where the sensor at t0 sees it (the
      // poses' velocity is the motion's own twist).
      ASSERT_EQ(r.features.points.size(), in.features.points.size());
      double worst = 0.0;
      for (std::size_t i = 0; i < in.features.points.size() && run == 0 && k > 0; ++i) {
        const Vec3 world = pose(in.features.stamps[i]) * in.features.points[i];
        worst = std::max(worst, (pose(t0) * r.features.points[i] - world).norm());
      }
      EXPECT_LT(worst, 1e-6) << k;
      if (!r.judged) continue;
      ASSERT_TRUE(r.pair.verdict.coral.valid) << r.reason;
      q[run] += r.pair.verdict.coral.quality / 3.0;
    }
  }
  std::printf("mean Q over 3 pairs: de-skewed %.3f, off %.3f, no times %.3f\n", q[0], q[1], q[2]);
  EXPECT_DOUBLE_EQ(q[1], q[2]);  // off or without times: the same scans as they arrived
  EXPECT_LT(3.0 * q[0], q[1]);   // de-skewed, the pairs are far more consistent
}

TEST(Introspector, FirstRadarScanIsDeskewedWithTheTwistTowardsTheSecond) {
  online::Introspector intro(radarConfig());
  std::mt19937 rng(4);
  online::ProcessOptions keep;
  keep.keep_scans = true;
  const Eigen::Isometry3d T0 = drivePose(0.0), T1 = drivePose(0.25);
  const online::ScanInput s0 = radarInput(10.0, rng, T0);
  const online::ScanInput s1 = radarInput(10.25, rng, T1);
  EXPECT_FALSE(intro.process(s0, keep).deskewed);  // no velocity yet
  const online::Report r = intro.process(s1, keep);
  ASSERT_TRUE(r.judged);
  radar::Twist v;
  ASSERT_TRUE(radar::twistBetween(T0, T1, 0.25, &v));
  radar::RadarFeatures f0 = s0.features, f1 = s1.features;
  radar::compensateMotion(v, 10.0, &f0);
  radar::compensateMotion(v, 10.25, &f1);
  ASSERT_EQ(r.pair.ref.points.size(), f0.points.size());
  for (std::size_t i = 0; i < f0.points.size(); ++i)
    ASSERT_EQ(r.pair.ref.points[i], f0.points[i]) << i;  // exactly the same computation
  const coral::Scan cur_in_ref = coral::transformScan(
      [&] {
        coral::Scan s;
        s.points = f1.points;
        return s;
      }(),
      T0.inverse() * T1);
  ASSERT_EQ(r.pair.cur.points.size(), cur_in_ref.points.size());
  for (std::size_t i = 0; i < cur_in_ref.points.size(); ++i)
    ASSERT_EQ(r.pair.cur.points[i], cur_in_ref.points[i]) << i;
  EXPECT_EQ(r.pair.cur.origin, (T0.inverse() * T1).translation());
}

TEST(Introspector, LoopingBagRestartsPairingAndClearsTheVelocityHistory) {
  online::Introspector intro(radarConfig());
  std::mt19937 rng(9);
  online::ProcessOptions keep;
  keep.keep_scans = true;
  for (int k = 0; k < 4; ++k)
    intro.process(radarInput(100.0 + 0.25 * k, rng, drivePose(0.25 * k)), keep);
  // The bag loops: time jumps back to the first stamp, the poses start again. A velocity
  // from the stale history (last pose at t = 0.75 s) would be a jump of metres.
  const online::ScanInput again0 = radarInput(100.0, rng, drivePose(0.0));
  const online::Report reset = intro.process(again0, keep);
  EXPECT_EQ(reset.action, PairAction::kBackwardsReset);
  EXPECT_FALSE(reset.judged);
  EXPECT_FALSE(reset.deskewed);  // history cleared: no velocity for the first scan
  EXPECT_NE(reset.reason.find("time jumped backwards"), std::string::npos) << reset.reason;
  EXPECT_EQ(intro.counters().time_resets, 1u);
  const online::Report next = intro.process(radarInput(100.25, rng, drivePose(0.25)), keep);
  EXPECT_EQ(next.action, PairAction::kPair);
  ASSERT_TRUE(next.hasVerdict()) << next.reason;
  EXPECT_TRUE(next.pair.verdict.aligned) << "Q = " << next.pair.verdict.coral.quality;
  EXPECT_DOUBLE_EQ(next.stamp_ref, 100.0);
  // The reset scan was de-skewed with the twist of the new sequence only.
  radar::Twist v;
  ASSERT_TRUE(radar::twistBetween(drivePose(0.0), drivePose(0.25), 0.25, &v));
  radar::RadarFeatures f = again0.features;
  radar::compensateMotion(v, 100.0, &f);
  ASSERT_EQ(next.pair.ref.points.size(), f.points.size());
  EXPECT_EQ(next.pair.ref.points.front(), f.points.front());
  EXPECT_EQ(next.pair.ref.points.back(), f.points.back());
}

TEST(Introspector, GapDuplicateAndTooCloseActions) {
  online::IntrospectorConfig c;
  c.pairing.max_time_gap = 1.0;
  c.pairing.min_distance = 0.5;
  online::Introspector intro(c);
  EXPECT_EQ(intro.process(tinyInput(1.0, Vec3(0, 0, 0))).action, PairAction::kFirst);
  const online::Report close = intro.process(tinyInput(1.1, Vec3(0.2, 0, 0)));
  EXPECT_EQ(close.action, PairAction::kTooClose);
  EXPECT_NE(close.reason.find("min_distance"), std::string::npos) << close.reason;
  EXPECT_EQ(intro.process(tinyInput(1.3, Vec3(1.0, 0, 0))).action, PairAction::kPair);
  const online::Report gap = intro.process(tinyInput(2.5, Vec3(2.0, 0, 0)));
  EXPECT_EQ(gap.action, PairAction::kGapReset);  // 1.2 s after the reference
  EXPECT_NE(gap.reason.find("max_time_gap"), std::string::npos) << gap.reason;
  const online::Report dup = intro.process(tinyInput(2.5, Vec3(3.0, 0, 0)));
  EXPECT_EQ(dup.action, PairAction::kDuplicateReset);
  EXPECT_FALSE(dup.judged);
  const online::Report after = intro.process(tinyInput(2.6, Vec3(4.0, 0, 0)));
  EXPECT_EQ(after.action, PairAction::kPair);
  EXPECT_TRUE(after.judged);
  EXPECT_FALSE(after.hasVerdict());  // 3 points: no overlap, and the report says why
  EXPECT_FALSE(after.reason.empty());
  const online::Counters& n = intro.counters();
  EXPECT_EQ(n.scans, 6u);
  EXPECT_EQ(n.too_close, 1u);
  EXPECT_EQ(n.gap_resets, 1u);
  EXPECT_EQ(n.duplicate_stamps, 1u);
  EXPECT_EQ(n.pairs, 2u);
  EXPECT_EQ(n.valid_pairs, 0u);
}

TEST(Introspector, TfFailureIsCountedAndLeavesTheStreamAlone) {
  online::Introspector intro(lidarConfig());
  std::mt19937 rng(6);
  auto pose = [](int k) { return coral::se2(-8.0 + 0.5 * k, -1.0, 0.0); };
  intro.process(lidarInput(0.0, pose(0), pose(0), rng));
  online::ScanInput lost = lidarInput(0.1, pose(1), pose(1), rng);
  lost.T_fixed_sensor.reset();
  lost.pose_error = "extrapolation into the future";
  const online::Report r = intro.process(lost);
  EXPECT_FALSE(r.has_pose);
  EXPECT_FALSE(r.judged);
  EXPECT_NE(r.reason.find("extrapolation into the future"), std::string::npos) << r.reason;
  EXPECT_EQ(r.counters.pose_failures, 1u);
  // The next scan pairs with the last scan that had a pose.
  const online::Report next = intro.process(lidarInput(0.2, pose(2), pose(2), rng));
  EXPECT_EQ(next.action, PairAction::kPair);
  EXPECT_DOUBLE_EQ(next.stamp_ref, 0.0);
  ASSERT_TRUE(next.hasVerdict()) << next.reason;
  EXPECT_TRUE(next.pair.verdict.aligned);
  // An empty scan is refused without touching the stream either.
  online::ScanInput empty = tinyInput(0.3, Vec3::Zero());
  empty.features.points.clear();
  EXPECT_FALSE(intro.process(empty).has_pose);
  EXPECT_EQ(intro.counters().empty_scans, 1u);
  EXPECT_EQ(intro.process(lidarInput(0.4, pose(3), pose(3), rng)).stamp_ref, 0.2);
}

TEST(Introspector, ResetStartsANewSequenceAndSetConfigValidates) {
  online::Introspector intro;
  intro.process(tinyInput(1.0, Vec3::Zero()));
  intro.reset();
  EXPECT_EQ(intro.process(tinyInput(1.1, Vec3(1, 0, 0))).action, PairAction::kFirst);
  online::IntrospectorConfig bad;
  bad.coral.radius = -1.0;
  std::string err;
  EXPECT_FALSE(intro.setConfig(bad, &err));
  EXPECT_NE(err.find("coral/radius"), std::string::npos) << err;
  EXPECT_DOUBLE_EQ(intro.config().coral.radius, online::IntrospectorConfig().coral.radius);
  online::IntrospectorConfig gap;
  gap.pairing.max_time_gap = 0.05;  // takes effect on the next scan, stream state kept
  ASSERT_TRUE(intro.setConfig(gap, &err)) << err;
  EXPECT_EQ(intro.process(tinyInput(1.2, Vec3(2, 0, 0))).action, PairAction::kGapReset);
}

// Every group of the verdict's settings is validated, under its parameter group's name:
// free_space/ once was not (bin_deg 0 threw in the free-space check), nor restart/ and
// registration/ (read as parameters since 2026-12-06).
TEST(IntrospectorConfig, ValidatesFreeSpaceRestartAndRegistration) {
  EXPECT_EQ(online::IntrospectorConfig().validate(), "");
  const struct {
    std::function<void(online::IntrospectorConfig*)> set;
    const char* message;
  } bad[] = {
      {[](online::IntrospectorConfig* c) { c->verdict.free_space.bin_deg = 0.0; },
       "free_space/bin_deg must be in (0, 10] deg (got 0)"},
      {[](online::IntrospectorConfig* c) { c->verdict.restart.directions = 0; },
       "restart/directions must be in [1, 64] (got 0)"},
      {[](online::IntrospectorConfig* c) { c->verdict.restart.registration.max_iterations = 0; },
       "registration/max_iterations must be in [1, 1000] (got 0)"},
  };
  for (const auto& b : bad) {
    online::IntrospectorConfig c;
    b.set(&c);
    EXPECT_NE(c.validate().find(b.message), std::string::npos) << c.validate();
  }
}

// The verdict's settings groups are validated from one list (VerdictConfig::problemsByGroup):
// a value broken in each group is reported by the core's validate() ("gate: ...") and by the
// nodelet's ("gate/..."), each under the group name the presets use.
TEST(IntrospectorConfig, EveryVerdictGroupIsValidatedByBoth) {
  online::IntrospectorConfig c;
  for (const coral::VerdictConfig::GroupProblems& g : c.verdict.problemsByGroup())
    EXPECT_EQ(g.problems, "") << g.group;
  c.verdict.classifier.threshold = 2.0;
  c.verdict.relative.margin = std::nan("");
  c.verdict.tolerance.translation = -1.0;
  c.verdict.gate.min_probability = 2.0;
  c.verdict.loop_closure.max_registered_offset = 1.0;
  c.verdict.free_space.bin_deg = 0.0;
  c.verdict.restart.directions = 0;
  c.verdict.restart.registration.max_iterations = 0;
  const std::vector<coral::VerdictConfig::GroupProblems> groups = c.verdict.problemsByGroup();
  ASSERT_EQ(groups.size(), 8u);
  const std::string core = c.verdict.validate(), node = c.validate();
  for (const coral::VerdictConfig::GroupProblems& g : groups) {
    EXPECT_NE(g.problems, "") << g.group << " (a value of each group is broken)";
    const std::string first = g.problems.substr(0, g.problems.find("; "));
    EXPECT_NE(core.find(std::string(g.group) + ": " + first), std::string::npos) << core;
    EXPECT_NE(node.find(std::string(g.group) + "/" + first), std::string::npos) << node;
  }
}

TEST(JudgePair, ExplainsWhyThereIsNoVerdict) {
  std::mt19937 rng(1);
  eval::LidarModel m;
  m.rings = 8;
  const auto scene = eval::SyntheticScene::structuredYard();
  coral::Scan a, b;
  a.points = eval::simulateScan(scene, coral::se2(-8, -1, 0), m, rng);
  b.points = eval::simulateScan(scene, coral::se2(-7.5, -1, 0), m, rng);
  const online::IntrospectorConfig cfg = lidarConfig();
  const online::PairJudgement ok =
      online::judgePair(a, b, coral::se2(-8, -1, 0).inverse() * coral::se2(-7.5, -1, 0), cfg, true);
  ASSERT_TRUE(ok.verdict.coral.valid) << ok.reason;
  EXPECT_TRUE(ok.reason.empty());
  EXPECT_TRUE(ok.verdict.aligned) << "Q = " << ok.verdict.coral.quality;
  EXPECT_EQ(ok.verdict.coral.per_point.size(), a.points.size() + b.points.size());
  // 100 m away: no overlap.
  const online::PairJudgement far = online::judgePair(a, b, coral::se2(100, 0, 0), cfg, false);
  EXPECT_FALSE(far.verdict.coral.valid);
  EXPECT_NE(far.reason.find("overlap"), std::string::npos) << far.reason;
  EXPECT_NE(far.reason.find("min_overlap"), std::string::npos) << far.reason;
}

// 4D radar: the odometry's velocity against the Doppler velocities. The simulated scans'
// polar noise is the configured noise model, so with point covariances the false-alarm
// rate at confidence 0.99 is near 1 %; without them the unmodelled bearing noise raises it.
TEST(Introspector, DopplerCheckUsesPointCovariances) {
  eval::DopplerSimConfig sim;  // 60 points, 30 % movers, 0.05 m/s Doppler noise
  auto run = [&](bool covariances, double speed_error, int n) {
    online::IntrospectorConfig c;
    c.doppler.enabled = true;
    c.doppler.point_covariances = covariances;
    c.doppler.noise = sim.position_noise;
    c.pairing.max_time_gap = 0.5;
    online::Introspector intro(c);
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int checked = 0, flagged = 0;
    for (int i = 0; i < n; ++i) {
      // Two scans per sequence (1 s apart from the next pair: a new sequence each time).
      const Vec3 v(1.75 + 1.25 * u(rng), 0.5 * u(rng), 0.2 * u(rng));
      const Vec3 v_odom = v + Vec3(speed_error, 0.0, 0.0);
      for (int k = 0; k < 2; ++k) {
        const eval::DopplerSimScan s = eval::simulateDopplerScan(v, sim, rng);
        online::ScanInput in;
        in.stamp = 1.0 * i + 0.1 * k;
        in.features.points = s.points;
        in.radial_velocity = s.radial_velocity;
        in.T_fixed_sensor = Eigen::Isometry3d(Eigen::Translation3d(v_odom * 0.1 * k));
        const online::Report r = intro.process(in);
        EXPECT_EQ(r.doppler.has_value(), k == 1);  // the first scan has no velocity
        if (!r.doppler || !r.doppler->result.valid) continue;
        EXPECT_LT((r.doppler->velocity_odometry - v_odom).norm(), 1e-9);
        ++checked;
        flagged += !r.doppler->result.consistent;
      }
    }
    EXPECT_GT(checked, 0.95 * n);
    return static_cast<double>(flagged) / checked;
  };
  const double with_cov = run(true, 0.0, 600), without = run(false, 0.0, 600);
  std::printf("false alarms at confidence 0.99: %.1f %% with covariances, %.1f %% without\n",
              100 * with_cov, 100 * without);
  EXPECT_LT(with_cov, 0.03);
  EXPECT_LT(with_cov, without);
  EXPECT_GT(run(true, 0.5, 100), 0.95);  // odometry 0.5 m/s fast: flagged
}
