// rostest: CoralNodelet's Doppler velocity-consistency output (see nodelet_doppler.test).
#include "coral_rostest_utils.hpp"
#include "rostest_main.hpp"

#include <sensor_msgs/point_cloud2_iterator.h>

#include <algorithm>
#include <map>

#include "coral_introspection/VelocityConsistency.h"
#include "coral_introspection/eval/doppler_simulation.hpp"

using namespace coral_test;
using coral_introspection::VelocityConsistency;

namespace {

constexpr double kPeriod = 0.1;  // [s] between scans (10 Hz 4D radar)
const std::string kNs = "/radar4d";
const std::string kFrame = "radar4d";
// Body velocity of coral_test::trajectory, hence the sensor-frame velocity at every scan.
const coral::Vec3 kTrueVelocity(3.0, 0.0, 0.0);

// The trajectory with its forward speed scaled (odometry with a speed error).
Eigen::Isometry3d scaledTrajectory(double t, double speed) {
  radar::Twist v;
  v.linear = coral::Vec3(speed, 0.0, 0.0);
  v.angular = coral::Vec3(0.0, 0.0, 0.3);
  return coral::se2(-5.0, -1.5, 0.1) * radar::constantVelocityPose(v, t);
}

// x, y, z, velocity (float32) cloud of a simulated Doppler scan.
sensor_msgs::PointCloud2 dopplerCloud(const eval::DopplerSimScan& s, const ros::Time& stamp) {
  sensor_msgs::PointCloud2 c;
  c.header.stamp = stamp;
  c.header.frame_id = kFrame;
  sensor_msgs::PointCloud2Modifier mod(c);
  mod.setPointCloud2Fields(
      4, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32, "z", 1,
      sensor_msgs::PointField::FLOAT32, "velocity", 1, sensor_msgs::PointField::FLOAT32);
  mod.resize(s.points.size());
  sensor_msgs::PointCloud2Iterator<float> it(c, "x"), v(c, "velocity");
  for (std::size_t i = 0; i < s.points.size(); ++i, ++it, ++v) {
    it[0] = static_cast<float>(s.points[i].x());
    it[1] = static_cast<float>(s.points[i].y());
    it[2] = static_cast<float>(s.points[i].z());
    *v = static_cast<float>(s.radial_velocity[i]);
  }
  return c;
}

// |v_Doppler - v_true| [m/s]: 3D and horizontal (vz is the weakly observed component of a
// radar with a narrow elevation field of view).
coral::Vec3 dopplerError(const VelocityConsistency& m) {
  return coral::Vec3(m.velocity_doppler.x, m.velocity_doppler.y, m.velocity_doppler.z) -
         kTrueVelocity;
}

class Doppler : public ::testing::Test {
 protected:
  void SetUp() override {
    // The nodelet's sign convention (set to the non-default in the .test): simulate with it.
    ASSERT_TRUE(ros::param::get(kNs + "/coral/doppler/radial_velocity_positive_away",
                                sim_.radial_velocity_positive_away));
    // The noise model the nodelet weights the points with (point covariances): simulate it.
    ASSERT_TRUE(
        ros::param::get(kNs + "/coral/doppler/sigma_range", sim_.position_noise.sigma_range));
    ASSERT_TRUE(
        ros::param::get(kNs + "/coral/doppler/sigma_azimuth", sim_.position_noise.sigma_azimuth));
    ASSERT_TRUE(ros::param::get(kNs + "/coral/doppler/sigma_elevation",
                                sim_.position_noise.sigma_elevation));
    sim_.num_points = 300;        // a 4D radar scan (static clutter + movers)
    sim_.outlier_fraction = 0.2;  // points on moving objects
    // sigma_doppler = 0.05 m/s (as configured).
    pub_ = nh_.advertise<sensor_msgs::PointCloud2>(kNs + "/scan", 10);
  }

  // Publishes n scans (TF from `pose`, Doppler from the true velocity); scans listed in
  // `no_field` lack the velocity field. Returns the messages keyed by scan index.
  template <class PoseFn>
  std::map<int, VelocityConsistency> run(Collector<VelocityConsistency>& out, int n, PoseFn pose,
                                         const std::vector<int>& no_field = {}) {
    static tf2_ros::TransformBroadcaster br;
    out.clear();
    ros::WallDuration(1.5).sleep();  // > pairing/max_time_gap: a fresh sequence
    const ros::Time base = ros::Time::now();
    std::vector<ros::Time> stamps;
    for (int i = 0; i < n; ++i) {
      const double t = i * kPeriod;
      const ros::Time stamp = base + ros::Duration(t);
      sendTf(br, pose(t), stamp, kFrame);
      ros::WallDuration(0.01).sleep();
      const auto scan = eval::simulateDopplerScan(kTrueVelocity, sim_, rng_);
      const bool drop = std::find(no_field.begin(), no_field.end(), i) != no_field.end();
      if (drop) {
        std_msgs::Header h;
        h.stamp = stamp;
        h.frame_id = kFrame;
        pub_.publish(ros_adapters::pointsToCloud(scan.points, h));  // x, y, z only
      } else {
        pub_.publish(dopplerCloud(scan, stamp));
      }
      stamps.push_back(stamp);
      ros::WallDuration(kPeriod - 0.01).sleep();
    }
    // One message per scan with a velocity field and a predecessor in the sequence.
    const std::size_t expected = static_cast<std::size_t>(n - 1 - no_field.size());
    out.waitFor(expected, 5.0);
    ros::WallDuration(0.3).sleep();  // anything late or unexpected
    std::map<int, VelocityConsistency> by_scan;
    for (const auto& m : out.all())
      for (int i = 0; i < n; ++i)
        if (m.header.stamp == stamps[i]) by_scan[i] = m;
    return by_scan;
  }

  ros::NodeHandle nh_;
  ros::Publisher pub_;
  eval::DopplerSimConfig sim_;
  std::mt19937 rng_{11};
};

TEST_F(Doppler, ConsistentTfAcceptedSpeedErrorFlaggedMissingFieldSkipped) {
  // Only the Doppler output is subscribed: it alone must wake the lazy input.
  Collector<VelocityConsistency> out(nh_, kNs + "/velocity_consistency");
  ASSERT_TRUE(waitForSubscriber(pub_)) << "nodelet did not subscribe to " << kNs << "/scan";
  const int n = 31;  // 30 checks per case (the first scan has no velocity yet)

  // (a) TF moves the sensor at the speed the Doppler velocities say.
  auto good = run(out, n, trajectory);
  int ok = 0, close = 0;
  double max_err = 0.0, sum_err = 0.0;
  for (const auto& [i, m] : good) {
    ASSERT_GT(i, 0) << "no velocity exists for the first scan of a sequence";
    EXPECT_EQ(m.header.frame_id, kFrame);
    EXPECT_EQ(m.dof, 3u);
    EXPECT_EQ(m.num_points, 300u);
    // TF velocity between consecutive scans, in the current sensor frame.
    EXPECT_NEAR(m.velocity_odometry.x, 3.0, 1e-3) << "scan " << i;
    EXPECT_NEAR(m.velocity_odometry.y, 0.0, 1e-3) << "scan " << i;
    EXPECT_NEAR(m.velocity_odometry.z, 0.0, 1e-3) << "scan " << i;
    if (m.valid && m.consistent) ++ok;
    if (!m.valid) continue;
    const coral::Vec3 e = dopplerError(m);
    const double err = e.norm();
    EXPECT_LT(e.head<2>().norm(), 0.1) << "scan " << i;
    if (err < 0.1) ++close;
    max_err = std::max(max_err, err);
    sum_err += err;
    EXPECT_GT(m.inlier_ratio, 0.6) << "scan " << i;  // 80 % static points
    EXPECT_EQ(m.chi2 <= m.threshold, static_cast<bool>(m.consistent)) << "scan " << i;
  }
  ROS_INFO(
      "(a) consistent TF: %zu messages, %d valid && consistent, %d with |v_D - v| < 0.1, "
      "|v_D - v| mean %.4f max %.4f m/s",
      good.size(), ok, close, good.empty() ? 0.0 : sum_err / good.size(), max_err);
  EXPECT_GE(ok, 0.9 * (n - 1)) << good.size() << " messages";
  EXPECT_GE(close, 0.9 * (n - 1)) << good.size() << " messages";
  EXPECT_LT(sum_err, 0.05 * (n - 1));  // mean 3D error below 5 cm/s

  // (b) Odometry 0.5 m/s too fast, Doppler unchanged.
  auto fast = run(out, n, [](double t) { return scaledTrajectory(t, 3.5); });
  int flagged = 0;
  double min_chi2 = 1e300, max_fast_err = 0.0;
  for (const auto& [i, m] : fast) {
    EXPECT_NEAR(m.velocity_odometry.x, 3.5, 1e-3) << "scan " << i;
    if (m.valid && !m.consistent) ++flagged;
    if (!m.valid) continue;
    min_chi2 = std::min(min_chi2, m.chi2 / m.threshold);
    const double err = dopplerError(m).norm();
    // The Doppler estimate does not follow the TF.
    EXPECT_LT(dopplerError(m).head<2>().norm(), 0.1) << "scan " << i;
    max_fast_err = std::max(max_fast_err, err);
  }
  ROS_INFO(
      "(b) TF 0.5 m/s fast: %zu messages, %d valid && !consistent, min chi2/threshold "
      "%.1f, max |v_D - v| %.4f m/s",
      fast.size(), flagged, min_chi2, max_fast_err);
  EXPECT_GE(flagged, 0.9 * (n - 1)) << fast.size() << " messages";

  // (c) Scan 3 has no velocity field: no message for it, no crash, scan 4 (velocity
  // from scan 3's pose) and later ones are checked again.
  const int n_c = 7, missing = 3;
  auto mixed = run(out, n_c, trajectory, {missing});
  EXPECT_EQ(mixed.count(missing), 0u);
  ASSERT_EQ(mixed.count(missing + 1), 1u) << "no message for the good cloud after the bad one";
  EXPECT_TRUE(mixed[missing + 1].valid);
  EXPECT_TRUE(mixed[missing + 1].consistent) << "chi2 = " << mixed[missing + 1].chi2;
  EXPECT_NEAR(mixed[missing + 1].velocity_odometry.x, 3.0, 1e-3);
  EXPECT_GE(mixed.size(), static_cast<std::size_t>(n_c - 2 - 1));  // allow one dropped scan
  ROS_INFO(
      "(c) no velocity field on scan %d: messages for %zu of %d scans, next scan valid %d "
      "consistent %d chi2 %.2f",
      missing, mixed.size(), n_c, mixed[missing + 1].valid, mixed[missing + 1].consistent,
      mixed[missing + 1].chi2);
}

}  // namespace

// main(): test/rostest/rostest_main.cpp.
const coral_test::RostestNode coral_test::kRostestNode{"nodelet_doppler_test", 2};
