// The one de-skew policy (radar/deskew.hpp): velocity from two poses, the median that
// ignores one odometry jump, the history of one sequence and the per-scan velocities of a
// recorded sequence.
#include <gtest/gtest.h>

#include "coral_introspection/radar/deskew.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::radar;

namespace {
Twist twist(double vx, double vy, double wz) {
  Twist t;
  t.linear = Vec3(vx, vy, 0.0);
  t.angular = Vec3(0.0, 0.0, wz);
  return t;
}
bool same(const Twist& a, const Twist& b, double tol = 1e-9) {
  return (a.linear - b.linear).norm() <= tol && (a.angular - b.angular).norm() <= tol;
}
}  // namespace

TEST(TwistBetween, InvertsTheConstantVelocityModel) {
  Twist v;
  v.linear = Vec3(5.0, 0.4, 0.1);
  v.angular = Vec3(0.02, 0.0, 0.8);
  const double dt = 0.25;
  const Eigen::Isometry3d T_fixed_prev = se2(3.0, -1.0, 0.4);
  const Eigen::Isometry3d T_fixed_curr = T_fixed_prev * constantVelocityPose(v, dt);
  Twist est;
  ASSERT_TRUE(twistBetween(T_fixed_prev, T_fixed_curr, dt, &est));
  EXPECT_TRUE(same(est, v));
  EXPECT_FALSE(twistBetween(T_fixed_prev, T_fixed_curr, 0.0, &est));
  EXPECT_FALSE(twistBetween(T_fixed_prev, T_fixed_curr, -0.1, &est));
}

TEST(MedianTwist, IgnoresOneOdometryJump) {
  const Twist good = twist(3.0, 0.0, 0.3);
  const Twist jump_in = twist(3.0, 2.0, 0.3);    // 0.5 m lateral jump over 0.25 s
  const Twist jump_out = twist(3.0, -2.0, 0.3);  // and back (a single displaced pose)
  EXPECT_TRUE(same(medianTwist({good, good, jump_in}), good, 1e-12));
  EXPECT_TRUE(same(medianTwist({good, jump_in, jump_out}), good, 1e-12));
  EXPECT_TRUE(same(medianTwist({}), Twist(), 0.0));
}

// Poses of a sensor at 4 Hz whose scan k (k = jump) is displaced 0.5 m sideways.
struct Sequence {
  std::vector<double> stamps;
  Isometries poses;
};
Sequence drive(int n, int jump = -1, double t0 = 100.0) {
  Sequence s;
  const Twist v = twist(3.0, 0.0, 0.3);
  for (int k = 0; k < n; ++k) {
    s.stamps.push_back(t0 + 0.25 * k);
    Eigen::Isometry3d T = se2(1.0, 2.0, 0.1) * constantVelocityPose(v, 0.25 * k);
    if (k == jump) T = T * Eigen::Translation3d(0.0, 0.5, 0.0);
    s.poses.push_back(T);
  }
  return s;
}

TEST(VelocityHistory, LatestUntilWindowFullThenMedianAndResetForgets) {
  const Sequence s = drive(6, 3);
  VelocityHistory h;  // window 3
  EXPECT_FALSE(h.add(s.stamps[0], s.poses[0]));
  EXPECT_FALSE(h.hasVelocity());
  for (int k = 1; k < 6; ++k) ASSERT_TRUE(h.add(s.stamps[k], s.poses[k]));
  // The last three intervals are 2-3 (jump in, +2 m/s sideways), 3-4 (jump out, -2 m/s)
  // and 4-5 (clean): the median is the clean motion up to the rotation coupling of the log.
  const Twist d = h.deskewVelocity();
  EXPECT_TRUE(same(d, twist(3.0, 0.0, 0.3), 0.1)) << d.linear.transpose();
  // The last interval alone is what the odometry says now.
  Twist last;
  ASSERT_TRUE(twistBetween(s.poses[4], s.poses[5], 0.25, &last));
  EXPECT_TRUE(same(h.lastTwist(), last, 0.0));
  h.reset();
  EXPECT_FALSE(h.hasVelocity());
  EXPECT_FALSE(h.add(s.stamps[5], s.poses[5]));  // first scan of a new sequence
  // A stamp that does not advance gives no twist but becomes the previous pose.
  EXPECT_FALSE(h.add(s.stamps[5], s.poses[5]));
}

TEST(DeskewVelocities, FirstScanUsesTheTwistTowardsTheSecondAndSequencesBreakOnTimeJumps) {
  Sequence s = drive(5);
  const Sequence again = drive(3, -1, 100.0);  // a looping bag: time jumps back
  s.stamps.insert(s.stamps.end(), again.stamps.begin(), again.stamps.end());
  s.poses.insert(s.poses.end(), again.poses.begin(), again.poses.end());
  const auto v = deskewVelocities(s.stamps, s.poses);
  ASSERT_EQ(v.size(), 8u);
  Twist t01, t12;
  ASSERT_TRUE(twistBetween(s.poses[0], s.poses[1], 0.25, &t01));
  ASSERT_TRUE(twistBetween(s.poses[1], s.poses[2], 0.25, &t12));
  for (std::size_t i = 0; i < v.size(); ++i) ASSERT_TRUE(v[i].has_value()) << i;
  EXPECT_TRUE(same(*v[0], t01, 0.0));  // scan 0: towards scan 1
  EXPECT_TRUE(same(*v[1], t01, 0.0));  // one interval known
  EXPECT_TRUE(same(*v[2], t12, 0.0));  // two: the latest
  EXPECT_TRUE(same(*v[4], twist(3.0, 0.0, 0.3), 1e-9));
  EXPECT_TRUE(same(*v[5], *v[6], 0.0));  // the new sequence's first scan: towards its second
  // A sequence of one scan has no velocity.
  const auto single = deskewVelocities({1.0}, Isometries{Eigen::Isometry3d::Identity()});
  ASSERT_EQ(single.size(), 1u);
  EXPECT_FALSE(single[0].has_value());
}

TEST(DeskewConfig, WindowMustBeOdd) {
  DeskewConfig c;
  EXPECT_TRUE(c.validate().empty());
  c.window = 2;
  EXPECT_NE(c.validate().find("window"), std::string::npos);
  c.window = 1;
  EXPECT_TRUE(c.validate().empty());
}
