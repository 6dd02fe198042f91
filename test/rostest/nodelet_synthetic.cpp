// rostest: CoralNodelet verdicts on synthetic sequences (see nodelet_synthetic.test).
#include "coral_rostest_utils.hpp"
#include "rostest_main.hpp"

#include <sensor_msgs/point_cloud2_iterator.h>

#include <map>

using namespace coral_test;
using coral_introspection::AlignmentQuality;

namespace {

constexpr double kPeriod = 0.25;  // [s] between scans

// Publishes n scans along the trajectory; scan `bad` (if >= 0) gets 0.5 m of lateral TF
// error in its own sensor frame. Returns the verdicts keyed by the index of scan b.
template <class MakeScan>
std::map<int, AlignmentQuality> runSequence(ros::Publisher& pub, Collector<AlignmentQuality>& out,
                                            const std::string& frame, int n, int bad, MakeScan make,
                                            std::vector<ros::Time>* stamps) {
  static tf2_ros::TransformBroadcaster br;
  out.clear();
  ros::WallDuration(1.5).sleep();  // > pairing/max_time_gap: a fresh pairing
  const ros::Time base = ros::Time::now();
  stamps->clear();
  for (int i = 0; i < n; ++i) {
    const double t = i * kPeriod;
    const ros::Time stamp = base + ros::Duration(t);
    Eigen::Isometry3d T = trajectory(t);
    if (i == bad) T = T * Eigen::Translation3d(0.0, 0.5, 0.0);  // odometry error
    sendTf(br, T, stamp, frame);
    ros::WallDuration(0.02).sleep();
    pub.publish(make(t, stamp));
    stamps->push_back(stamp);
    ros::WallDuration(kPeriod).sleep();
  }
  EXPECT_TRUE(out.waitFor(n - 1, 30.0)) << "got " << out.size() << " verdicts";
  std::map<int, AlignmentQuality> by_b;
  for (const auto& m : out.all())
    for (int i = 0; i < n; ++i)
      if (m.stamp_b == (*stamps)[i]) by_b[i] = m;
  return by_b;
}

double meanQ(const sensor_msgs::PointCloud2& c, const std::function<bool(float, float, float)>& sel,
             int* count) {
  sensor_msgs::PointCloud2ConstIterator<float> it(c, "x");
  double sum = 0.0;
  *count = 0;
  for (std::size_t i = 0; i < c.width * c.height; ++i, ++it)
    if (sel(it[0], it[1], it[2])) {
      sum += it[3];  // q follows x, y, z
      ++*count;
    }
  return *count > 0 ? sum / *count : 0.0;
}

class Synthetic : public ::testing::Test {
 protected:
  ros::NodeHandle nh;
  std::mt19937 rng{7};
};

TEST_F(Synthetic, LidarCorrectTfAlignedAndTfErrorFlagged) {
  Collector<AlignmentQuality> verdicts(nh, "/lidar/alignment");
  Collector<sensor_msgs::PointCloud2> quality(nh, "/lidar/quality_cloud");
  ros::Publisher pub = nh.advertise<sensor_msgs::PointCloud2>("/lidar/scan", 10);
  ASSERT_TRUE(waitForSubscriber(pub)) << "nodelet did not subscribe to /lidar/scan (lazy input)";
  auto make = [&](double t, const ros::Time& stamp) {
    return lidarCloud(trajectory(t), stamp, "lidar", rng);
  };
  std::vector<ros::Time> stamps;
  const int n = 7, bad = 3;

  auto ok = runSequence(pub, verdicts, "lidar", n, -1, make, &stamps);
  ASSERT_EQ(ok.size(), static_cast<std::size_t>(n - 1));
  for (const auto& [i, m] : ok) {
    EXPECT_TRUE(m.valid) << "pair ending at scan " << i;
    EXPECT_TRUE(m.aligned) << "pair ending at scan " << i << " Q = " << m.quality
                           << " p = " << m.probability;
    EXPECT_EQ(m.header.frame_id, "odom");
    EXPECT_EQ(m.stamp_a, stamps[i - 1]);
  }

  quality.clear();
  auto err = runSequence(pub, verdicts, "lidar", n, bad, make, &stamps);
  ASSERT_EQ(err.size(), static_cast<std::size_t>(n - 1));
  for (const auto& [i, m] : err) {
    const bool straddles = i == bad || i == bad + 1;
    EXPECT_TRUE(m.valid) << "pair ending at scan " << i;
    EXPECT_EQ(m.aligned, !straddles)
        << "pair ending at scan " << i << " Q = " << m.quality << " p = " << m.probability;
  }
  EXPECT_GT(err[bad].quality, 5.0 * ok[bad].quality);

  // Per-point q of the flagged pair: high on walls facing the (mostly +y) displacement,
  // near zero on the floor, which slides within its own plane.
  ASSERT_TRUE(quality.waitFor(n - 1, 10.0));
  sensor_msgs::PointCloud2 flagged, clean;
  for (const auto& c : quality.all()) {
    if (c.header.stamp == stamps[bad]) flagged = c;
    if (c.header.stamp == stamps[bad + 2]) clean = c;
  }
  ASSERT_GT(flagged.width, 100u);
  ASSERT_GT(clean.width, 100u);
  auto wall_y = [](float, float y, float z) { return std::abs(y) > 9.0f && z > -1.0f; };
  auto floor = [](float, float, float z) { return z < -1.3f; };
  int n_wall = 0, n_floor = 0, n_clean = 0;
  const double q_wall = meanQ(flagged, wall_y, &n_wall);
  const double q_floor = meanQ(flagged, floor, &n_floor);
  const double q_clean = meanQ(clean, wall_y, &n_clean);
  ROS_INFO(
      "lidar per-point q: displaced walls %.3f (%d pts), floor %.3f (%d), clean walls %.3f (%d)",
      q_wall, n_wall, q_floor, n_floor, q_clean, n_clean);
  EXPECT_GT(n_wall, 50);
  EXPECT_GT(n_floor, 50);
  EXPECT_GT(q_wall, 5.0 * q_clean);
  EXPECT_GT(q_wall, 5.0 * q_floor);
}

// sensor_msgs/LaserScan straight into the nodelet (input_type laser_scan, lidar_2d): 0.5 deg
// beams, no returns written at range_max; correct TF aligned, the TF error flagged.
TEST_F(Synthetic, LaserScanCorrectTfAlignedAndTfErrorFlagged) {
  Collector<AlignmentQuality> verdicts(nh, "/laser/alignment");
  ros::Publisher pub = nh.advertise<sensor_msgs::LaserScan>("/laser/scan", 10);
  ASSERT_TRUE(waitForSubscriber(pub)) << "nodelet did not subscribe to /laser/scan";
  auto make = [&](double t, const ros::Time& stamp) {
    return laserScan(trajectory(t), stamp, "laser", rng);
  };
  std::vector<ros::Time> stamps;
  const int n = 7, bad = 3;
  auto ok = runSequence(pub, verdicts, "laser", n, -1, make, &stamps);
  ASSERT_EQ(ok.size(), static_cast<std::size_t>(n - 1));
  for (const auto& [i, m] : ok) {
    EXPECT_TRUE(m.valid) << "pair ending at scan " << i << ": " << m.reason;
    EXPECT_TRUE(m.aligned) << "pair ending at scan " << i << " Q = " << m.quality
                           << " p = " << m.probability << " " << m.reason;
    EXPECT_GT(m.num_points_a, 50u);
    EXPECT_LE(m.num_points_a, 181u);  // thinned to 1 deg: at most 181 of the 361 beams
  }
  auto err = runSequence(pub, verdicts, "laser", n, bad, make, &stamps);
  ASSERT_EQ(err.size(), static_cast<std::size_t>(n - 1));
  for (const auto& [i, m] : err) {
    const bool straddles = i == bad || i == bad + 1;
    EXPECT_TRUE(m.valid) << "pair ending at scan " << i;
    EXPECT_EQ(m.aligned, !straddles) << "pair ending at scan " << i << " Q = " << m.quality
                                     << " p = " << m.probability << " " << m.reason;
  }
}

TEST_F(Synthetic, PolarImageCorrectTfAlignedAndTfErrorFlagged) {
  Collector<AlignmentQuality> verdicts(nh, "/radar/alignment");
  Collector<sensor_msgs::PointCloud2> features(nh, "/radar/features");
  ros::Publisher pub = nh.advertise<sensor_msgs::Image>("/radar/polar_image", 10);
  ASSERT_TRUE(waitForSubscriber(pub)) << "nodelet did not subscribe to /radar/polar_image";
  // The image is rendered from the moving (true) trajectory row by row, as a spinning
  // radar sees it; the nodelet de-skews it with the TF velocity.
  auto make = [&](double t, const ros::Time& stamp) {
    return polarImage(trajectory, t, stamp, "radar");
  };
  std::vector<ros::Time> stamps;
  const int n = 7, bad = 3;
  auto ok = runSequence(pub, verdicts, "radar", n, -1, make, &stamps);
  ASSERT_EQ(ok.size(), static_cast<std::size_t>(n - 1));
  for (const auto& [i, m] : ok) {
    EXPECT_TRUE(m.valid) << "pair ending at scan " << i;
    EXPECT_TRUE(m.aligned) << "pair ending at scan " << i << " Q = " << m.quality;
    EXPECT_GT(m.num_points_a, 200u);  // about one RIP feature per azimuth
  }
  auto err = runSequence(pub, verdicts, "radar", n, bad, make, &stamps);
  ASSERT_EQ(err.size(), static_cast<std::size_t>(n - 1));
  for (const auto& [i, m] : err) {
    const bool straddles = i == bad || i == bad + 1;
    EXPECT_TRUE(m.valid) << "pair ending at scan " << i;
    EXPECT_EQ(m.aligned, !straddles) << "pair ending at scan " << i << " Q = " << m.quality;
  }
  // Features are published in the radar frame.
  ASSERT_TRUE(features.waitFor(1, 5.0));
  EXPECT_EQ(features.all().front().header.frame_id, "radar");
  EXPECT_GT(features.all().front().width, 200u);
}

}  // namespace

// main(): test/rostest/rostest_main.cpp.
const coral_test::RostestNode coral_test::kRostestNode{"nodelet_synthetic_test", 2};
