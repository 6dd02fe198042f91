// `rosbag play` of the bag written by oxford_to_bag (writeOxfordBag): every image and TF
// arrives on its topic, and the replayed TF reproduces the GT relative poses.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <tf2_msgs/TFMessage.h>

#include <unistd.h>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <vector>

#include "coral_introspection/eval/oxford_dataset.hpp"
#include "coral_introspection/ros/conversions.hpp"
#include "coral_introspection/ros_eval/oxford_bag_writer.hpp"
#include "rostest_main.hpp"
#include "support/test_data.hpp"

namespace ra = coral_introspection::ros_adapters;
namespace ros_eval = coral_introspection::ros_eval;

TEST(OxfordBagPlay, RosbagPlayDeliversImagesAndTf) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  const std::string bag = coral_test::tempPath("oxford_play", ".bag");
  std::string err;
  ASSERT_TRUE(
      ros_eval::writeOxfordBag(coral_data, bag, ros_eval::OxfordBagOptions(), nullptr, &err))
      << err;
  coral_introspection::eval::OxfordDataset ds;
  ASSERT_TRUE(ds.load(coral_data, &err)) << err;

  ros::NodeHandle nh;
  std::mutex mutex;
  std::vector<sensor_msgs::Image> images;
  std::vector<geometry_msgs::TransformStamped> tfs;
  ros::Subscriber si = nh.subscribe<sensor_msgs::Image>("/radar/polar", 20,
                                                        [&](const sensor_msgs::ImageConstPtr& m) {
                                                          std::lock_guard<std::mutex> l(mutex);
                                                          images.push_back(*m);
                                                        });
  ros::Subscriber st =
      nh.subscribe<tf2_msgs::TFMessage>("/tf", 20, [&](const tf2_msgs::TFMessageConstPtr& m) {
        std::lock_guard<std::mutex> l(mutex);
        for (const auto& t : m->transforms) tfs.push_back(t);
      });
  ros::AsyncSpinner spinner(2);
  spinner.start();
  // -d 1: wait after advertising so that our subscribers are connected before playback.
  const std::string cmd = "rosbag play -q -d 1 " + bag;
  const int rc = std::system(cmd.c_str());
  ASSERT_EQ(rc, 0) << cmd;
  for (int i = 0; i < 50; ++i) {  // let the last messages arrive
    {
      std::lock_guard<std::mutex> l(mutex);
      if (images.size() >= 11 && tfs.size() >= 11) break;
    }
    ros::Duration(0.1).sleep();
  }
  spinner.stop();
  std::remove(bag.c_str());
  std::lock_guard<std::mutex> l(mutex);
  ASSERT_EQ(images.size(), 11u);
  ASSERT_EQ(tfs.size(), 11u);
  for (std::size_t i = 0; i < 11; ++i) {
    EXPECT_EQ(images[i].header.stamp.toNSec(), static_cast<uint64_t>(ds.stamps_us[i]) * 1000u);
    EXPECT_EQ(images[i].width, 3779u);
    EXPECT_EQ(images[i].height, 400u);
    EXPECT_EQ(tfs[i].header.stamp, images[i].header.stamp);
    EXPECT_EQ(tfs[i].header.frame_id, "odom");
    EXPECT_EQ(tfs[i].child_frame_id, "radar");
  }
  for (std::size_t i = 1; i < 11; ++i) {
    Eigen::Isometry3d a, b;
    ASSERT_TRUE(ra::toEigen(tfs[i - 1].transform, &a, &err)) << err;
    ASSERT_TRUE(ra::toEigen(tfs[i].transform, &b, &err)) << err;
    const Eigen::Isometry3d diff = ds.T_prev_curr[i].inverse() * (a.inverse() * b);
    EXPECT_LT(diff.translation().norm(), 1e-3) << "pair " << i;
    EXPECT_LT(Eigen::AngleAxisd(diff.rotation()).angle() * 180.0 / M_PI, 0.01) << "pair " << i;
  }
}

// main(): test/rostest/rostest_main.cpp.
const coral_test::RostestNode coral_test::kRostestNode{"oxford_bag_play_test", 0};
