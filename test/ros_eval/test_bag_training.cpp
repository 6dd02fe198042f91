// coral_train's rosbag input (no ROS master): an Oxford bag (polar images + GT TF) must give
// the same scans and poses as the Oxford folder reader, and a PointCloud2 bag with
// nav_msgs/Odometry (+ a static extrinsic) must give the simulated sensor poses.
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <tf2_msgs/TFMessage.h>

#include <unistd.h>
#include <random>

#include "coral_introspection/eval/oxford_training.hpp"
#include "coral_introspection/eval/synthetic.hpp"
#include "coral_introspection/ros/conversions.hpp"
#include "coral_introspection/ros_eval/bag_training_reader.hpp"
#include "coral_introspection/ros_eval/oxford_bag_writer.hpp"
#include "support/test_data.hpp"

namespace ra = coral_introspection::ros_adapters;
namespace ros_eval = coral_introspection::ros_eval;
namespace coral = coral_introspection::coral;
namespace eval = coral_introspection::eval;

static std::string tempBag(const std::string& name) { return coral_test::tempPath(name, ".bag"); }

TEST(BagTraining, OxfordBagMatchesTheFolderReader) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  ros::Time::init();
  const std::string path = tempBag("train_oxford");
  ros_eval::OxfordBagSummary written;
  std::string err;
  ASSERT_TRUE(
      ros_eval::writeOxfordBag(coral_data, path, ros_eval::OxfordBagOptions(), &written, &err))
      << err;

  EXPECT_EQ(ros_eval::bagTopicType(path, "/radar/polar"), "sensor_msgs/Image");
  EXPECT_EQ(ros_eval::bagTopicType(path, "/nothing"), "");
  ros_eval::BagTrainingOptions o;
  o.scan_topic = "/radar/polar";
  o.fixed_frame = "odom";
  std::vector<eval::TrainingScan> scans;
  coral::Isometries poses;
  ros_eval::BagTrainingSummary sum;
  ASSERT_TRUE(ros_eval::loadBagTrainingScans(path, o, nullptr, &scans, &poses, &sum, &err)) << err;
  EXPECT_TRUE(sum.radar_images);
  EXPECT_EQ(sum.no_pose, 0u);
  ASSERT_EQ(scans.size(), 11u);

  eval::OxfordDataset ds;
  ASSERT_TRUE(ds.load(coral_data, &err)) << err;
  std::vector<eval::TrainingScan> ref;
  coral::Isometries ref_poses;
  ASSERT_TRUE(eval::loadOxfordTrainingScans(ds, eval::OxfordTrainingConfig(), nullptr, &ref,
                                            &ref_poses, &err))
      << err;
  for (std::size_t i = 0; i < scans.size(); ++i) {
    EXPECT_TRUE(poses[i].isApprox(ref_poses[i], 1e-6)) << i;
    EXPECT_EQ(scans[i].scan.points.size(), ref[i].scan.points.size()) << i;
    EXPECT_EQ(scans[i].cfear_points.size(), ref[i].cfear_points.size()) << i;
    // Same features after motion compensation (same velocity, same reference time).
    for (std::size_t k = 0; k < scans[i].scan.points.size(); k += 97)
      EXPECT_LT((scans[i].scan.points[k] - ref[i].scan.points[k]).norm(), 1e-3) << i << " " << k;
    for (std::size_t k = 0; k < scans[i].cfear_points.size(); k += 97)
      EXPECT_LT((scans[i].cfear_points[k] - ref[i].cfear_points[k]).norm(), 1e-3) << i << " " << k;
  }
  std::remove(path.c_str());
}

TEST(BagTraining, PointCloudsWithOdometryAndStaticExtrinsic) {
  ros::Time::init();
  const std::string path = tempBag("train_clouds");
  const Eigen::Isometry3d T_base_lidar =
      coral::se2(0.5, 0.0, 0.0) * Eigen::Translation3d(0, 0, 1.0);
  std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>> T_odom_base;
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    tf2_msgs::TFMessage st;
    geometry_msgs::TransformStamped ext;
    ext.header.stamp = ros::Time(100.0);
    ext.header.frame_id = "base_link";
    ext.child_frame_id = "lidar";
    ext.transform = ra::toTransformMsg(T_base_lidar);
    st.transforms.push_back(ext);
    bag.write("/tf_static", ros::Time(100.0), st);
    std::mt19937 rng(1);
    eval::LidarModel lidar;
    lidar.azimuths = 180;
    lidar.rings = 4;
    for (int i = 0; i < 4; ++i) {
      const ros::Time t(100.0 + 0.1 * (i + 1));
      T_odom_base.push_back(coral::se2(0.3 * i, 0.1 * i, 0.02 * i));
      // Odometry at a slightly earlier and later time: the reader interpolates.
      for (double dt : {-0.01, 0.01}) {
        nav_msgs::Odometry od;
        od.header.stamp = t + ros::Duration(dt);
        od.header.frame_id = "odom";
        od.child_frame_id = "base_link";
        const Eigen::Isometry3d T = T_odom_base.back() * coral::se2(dt * 3.0, 0.0, 0.0);
        const geometry_msgs::Transform tr = ra::toTransformMsg(T);
        od.pose.pose.position.x = tr.translation.x;
        od.pose.pose.position.y = tr.translation.y;
        od.pose.pose.position.z = tr.translation.z;
        od.pose.pose.orientation = tr.rotation;
        bag.write("/odom", od.header.stamp, od);
      }
      std_msgs::Header h;
      h.stamp = t;
      h.frame_id = "lidar";
      const coral::Points pts = eval::simulateScan(eval::SyntheticScene::structuredYard(),
                                                   T_odom_base.back() * T_base_lidar, lidar, rng);
      bag.write("/points", t, ra::pointsToCloud(pts, h));
    }
    // A scan before any pose: skipped and counted, not fatal.
    std_msgs::Header h;
    h.stamp = ros::Time(150.0);
    h.frame_id = "lidar";
    bag.write("/points", h.stamp, ra::pointsToCloud(coral::Points{{1, 2, 3}}, h));
  }
  ros_eval::BagTrainingOptions o;
  o.scan_topic = "/points";
  o.odom_topic = "/odom";
  std::vector<eval::TrainingScan> scans;
  coral::Isometries poses;
  ros_eval::BagTrainingSummary sum;
  std::string err;
  ASSERT_TRUE(ros_eval::loadBagTrainingScans(path, o, nullptr, &scans, &poses, &sum, &err)) << err;
  EXPECT_FALSE(sum.radar_images);
  EXPECT_EQ(sum.scan_messages, 5u);
  EXPECT_EQ(sum.no_pose, 1u);
  ASSERT_EQ(scans.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    const Eigen::Isometry3d expected = T_odom_base[i] * T_base_lidar;  // T_odom_lidar
    EXPECT_LT((poses[i].translation() - expected.translation()).norm(), 1e-6) << i;
    EXPECT_TRUE(poses[i].linear().isApprox(expected.linear(), 1e-6)) << i;
    EXPECT_GT(scans[i].scan.points.size(), 100u);
    EXPECT_TRUE(scans[i].cfear_points.empty());
  }
  EXPECT_FALSE(
      ros_eval::loadBagTrainingScans("/nonexistent.bag", o, nullptr, &scans, &poses, &sum, &err));
  EXPECT_NE(err.find("nonexistent"), std::string::npos);
  std::remove(path.c_str());
}
