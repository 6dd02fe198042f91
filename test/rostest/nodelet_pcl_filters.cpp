// rostest: pcl_ros CropBox -> VoxelGrid -> CoralNodelet in one manager
// (launch/coral_pcl_filters.launch, see nodelet_pcl_filters.test). The filters really run
// (cropped clouds inside the box, voxel clouds smaller still), and CorAl's verdicts on the
// filtered clouds are those of the raw ones: aligned with correct TF, the two pairs around a
// 0.5 m TF error flagged.
#include "coral_rostest_utils.hpp"
#include "rostest_main.hpp"

#include <sensor_msgs/point_cloud2_iterator.h>

#include <algorithm>
#include <map>

using namespace coral_test;
using coral_introspection::AlignmentQuality;

namespace {

constexpr double kPeriod = 0.25;  // [s] between scans
// The box of nodelet_pcl_filters.test, in the sensor frame [m].
constexpr float kBoxXY = 12.0f, kBoxZMin = -3.0f, kBoxZMax = 5.0f;

// Points of `c` outside the test's crop box.
int outsideBox(const sensor_msgs::PointCloud2& c) {
  int n = 0;
  for (sensor_msgs::PointCloud2ConstIterator<float> it(c, "x"); it != it.end(); ++it)
    if (std::abs(it[0]) > kBoxXY || std::abs(it[1]) > kBoxXY || it[2] < kBoxZMin ||
        it[2] > kBoxZMax)
      ++n;
  return n;
}

TEST(PclFilters, CropBoxVoxelGridCoralNodeletInOneManager) {
  ros::NodeHandle nh;
  tf2_ros::TransformBroadcaster br;  // early: its first message must not be lost
  Collector<AlignmentQuality> verdicts(nh, "/alignment");
  Collector<sensor_msgs::PointCloud2> cropped(nh, "/crop_box/output");
  Collector<sensor_msgs::PointCloud2> voxels(nh, "/voxel_grid/output");
  Collector<sensor_msgs::PointCloud2> quality(nh, "/quality_cloud");
  Collector<sensor_msgs::PointCloud2> high_q(nh, "/high_q/output");
  ros::Publisher pub = nh.advertise<sensor_msgs::PointCloud2>("/points", 10);
  // The chain is lazy end to end: CoralNodelet subscribes to voxel_grid/output once its
  // alignment topic has a subscriber, VoxelGrid then to crop_box/output, CropBox to /points.
  ASSERT_TRUE(waitForSubscriber(pub, 30.0)) << "CropBox did not subscribe to /points";
  ros::WallDuration(1.0).sleep();  // TF connections

  std::mt19937 rng(11);
  const int n = 7, bad = 3;
  // Whole microseconds: pcl_ros's filters pass the stamp through PCL's header, which holds
  // microseconds, so stamps compare equal after the filters only at that precision.
  const ros::Time base = ros::Time().fromNSec(ros::Time::now().toNSec() / 1000 * 1000);
  std::vector<ros::Time> stamps;
  std::map<ros::Time, std::size_t> raw_size;
  for (int i = 0; i < n; ++i) {
    const double t = i * kPeriod;
    const ros::Time stamp = base + ros::Duration(t);
    Eigen::Isometry3d T = trajectory(t);
    if (i == bad) T = T * Eigen::Translation3d(0.0, 0.5, 0.0);  // odometry error
    sendTf(br, T, stamp, "lidar");
    ros::WallDuration(0.02).sleep();
    const sensor_msgs::PointCloud2 raw = lidarCloud(trajectory(t), stamp, "lidar", rng);
    raw_size[stamp] = raw.width;
    pub.publish(raw);
    stamps.push_back(stamp);
    ros::WallDuration(kPeriod).sleep();
  }
  ASSERT_TRUE(verdicts.waitFor(n - 1, 30.0)) << "got " << verdicts.size() << " verdicts";
  ASSERT_TRUE(cropped.waitFor(n, 5.0));
  ASSERT_TRUE(voxels.waitFor(n, 5.0));

  // The filters ran: frame and stamp kept, points only inside the box, fewer after the grid.
  for (const auto& c : cropped.all()) {
    EXPECT_EQ(c.header.frame_id, "lidar");
    EXPECT_GT(c.width * c.height, 500u);
    EXPECT_LT(c.width * c.height, raw_size[c.header.stamp]) << "the box removed nothing";
    EXPECT_EQ(outsideBox(c), 0);
  }
  std::size_t max_voxels = 0;
  for (const auto& v : voxels.all()) {
    EXPECT_EQ(v.header.frame_id, "lidar");
    max_voxels = std::max<std::size_t>(max_voxels, v.width * v.height);
  }
  std::map<ros::Time, std::size_t> crop_size;
  for (const auto& c : cropped.all()) crop_size[c.header.stamp] = c.width * c.height;
  for (const auto& v : voxels.all()) {
    ASSERT_EQ(crop_size.count(v.header.stamp), 1u);
    EXPECT_LT(v.width * v.height, crop_size[v.header.stamp]);
  }

  // CorAl's verdicts on the filtered clouds.
  std::map<int, AlignmentQuality> by_b;
  for (const auto& m : verdicts.all())
    for (int i = 0; i < n; ++i)
      if (m.stamp_b == stamps[i]) by_b[i] = m;
  ASSERT_EQ(by_b.size(), static_cast<std::size_t>(n - 1));
  for (const auto& [i, m] : by_b) {
    const bool straddles = i == bad || i == bad + 1;
    EXPECT_TRUE(m.valid) << "pair ending at scan " << i << ": " << m.reason;
    EXPECT_EQ(m.aligned, !straddles)
        << "pair ending at scan " << i << " Q = " << m.quality << " p = " << m.probability;
    EXPECT_GT(m.num_points_b, 0u);
    EXPECT_LE(m.num_points_b, max_voxels) << "CorAl saw more points than VoxelGrid sent";
  }

  // pcl_ros PassThrough on the quality cloud, in the same manager: every kept point has
  // q >= 0.5, and the flagged pair has more of them than the clean pair after it.
  ASSERT_TRUE(quality.waitFor(n - 1, 5.0));
  ASSERT_TRUE(high_q.waitFor(n - 1, 5.0)) << "got " << high_q.size() << " PassThrough clouds";
  std::map<ros::Time, std::size_t> kept;
  for (const auto& c : high_q.all()) {
    EXPECT_EQ(c.header.frame_id, "odom");
    std::size_t k = 0;
    for (sensor_msgs::PointCloud2ConstIterator<float> q(c, "q"); q != q.end(); ++q, ++k)
      EXPECT_GE(*q, 0.5f);
    kept[c.header.stamp] = k;
  }
  ROS_INFO("points with q >= 0.5: flagged pair %zu, clean pair %zu", kept[stamps[bad]],
           kept[stamps[bad + 2]]);
  EXPECT_GT(kept[stamps[bad]], kept[stamps[bad + 2]]);
}

}  // namespace

// main(): test/rostest/rostest_main.cpp.
const coral_test::RostestNode coral_test::kRostestNode{"nodelet_pcl_filters_test", 2};
