// Oxford folder -> rosbag conversion (no ROS master): read the bag back with the rosbag
// API and check images and the ground-truth TF. Skips without ../shared/data.
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Image.h>
#include <tf2_msgs/TFMessage.h>

#include <unistd.h>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>

#include "coral_introspection/eval/oxford_dataset.hpp"
#include "coral_introspection/radar/polar_scan.hpp"
#include "coral_introspection/ros/conversions.hpp"
#include "coral_introspection/ros_eval/oxford_bag_writer.hpp"
#include "support/test_data.hpp"

namespace ra = coral_introspection::ros_adapters;
namespace ros_eval = coral_introspection::ros_eval;
namespace radar = coral_introspection::radar;
namespace eval = coral_introspection::eval;

static std::string tempBag(const std::string& name) { return coral_test::tempPath(name, ".bag"); }

TEST(OxfordToBag, ImagesAndGroundTruthTfRoundTrip) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  ros::Time::init();
  const std::string path = tempBag("oxford");
  ros_eval::OxfordBagSummary sum;
  std::string err;
  ASSERT_TRUE(ros_eval::writeOxfordBag(coral_data, path, ros_eval::OxfordBagOptions(), &sum, &err))
      << err;
  EXPECT_EQ(sum.images, 11u);
  EXPECT_EQ(sum.transforms, 11u);
  EXPECT_NEAR(sum.duration_s, 2.491696, 1e-6);

  eval::OxfordDataset ds;
  ASSERT_TRUE(ds.load(coral_data, &err)) << err;
  std::vector<sensor_msgs::Image> images;
  std::vector<geometry_msgs::TransformStamped> tfs;
  {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
      if (m.getTopic() == "/radar/polar") {
        auto img = m.instantiate<sensor_msgs::Image>();
        ASSERT_TRUE(img);
        EXPECT_EQ(m.getTime(), img->header.stamp);
        images.push_back(*img);
      } else if (m.getTopic() == "/tf") {
        auto tf = m.instantiate<tf2_msgs::TFMessage>();
        ASSERT_TRUE(tf);
        ASSERT_EQ(tf->transforms.size(), 1u);
        EXPECT_LT(m.getTime(), tf->transforms[0].header.stamp);  // recorded just before
        tfs.push_back(tf->transforms[0]);
      } else {
        ADD_FAILURE() << "unexpected topic " << m.getTopic();
      }
    }
  }
  std::remove(path.c_str());
  ASSERT_EQ(images.size(), 11u);
  ASSERT_EQ(tfs.size(), 11u);
  for (std::size_t i = 0; i < 11; ++i) {
    const sensor_msgs::Image& img = images[i];
    EXPECT_EQ(img.header.stamp.toNSec(), static_cast<uint64_t>(ds.stamps_us[i]) * 1000u);
    EXPECT_EQ(img.header.frame_id, "radar");
    EXPECT_EQ(img.encoding, "mono8");
    EXPECT_EQ(img.height, 400u);
    EXPECT_EQ(img.width, 3779u);
    EXPECT_EQ(img.step, 3779u);
    ASSERT_EQ(img.data.size(), 400u * 3779u);
    // Byte-identical to the PNG, so the per-row metadata decodes to the same scan.
    const cv::Mat png = cv::imread(ds.png_paths[i], cv::IMREAD_UNCHANGED);
    const cv::Mat wrapped(400, 3779, CV_8UC1, const_cast<uint8_t*>(img.data.data()));
    EXPECT_EQ(cv::norm(png, wrapped, cv::NORM_INF), 0.0);
    radar::PolarScan scan;
    ASSERT_TRUE(radar::decodeOxfordImage(wrapped, &scan, &err)) << err;
    EXPECT_NEAR(scan.stamp, img.header.stamp.toSec(), 1e-6);

    EXPECT_EQ(tfs[i].header.frame_id, "odom");
    EXPECT_EQ(tfs[i].child_frame_id, "radar");
    EXPECT_EQ(tfs[i].header.stamp, img.header.stamp);
  }
  // Relative poses between consecutive TFs reproduce the GT within 1 mm / 0.01 deg.
  Eigen::Isometry3d prev;
  ASSERT_TRUE(ra::toEigen(tfs[0].transform, &prev, &err)) << err;
  EXPECT_TRUE(prev.isApprox(Eigen::Isometry3d::Identity(), 1e-12));
  for (std::size_t i = 1; i < 11; ++i) {
    Eigen::Isometry3d curr;
    ASSERT_TRUE(ra::toEigen(tfs[i].transform, &curr, &err)) << err;
    const Eigen::Isometry3d rel = prev.inverse() * curr;  // T_{i-1}_i from the bag
    const Eigen::Isometry3d diff = ds.T_prev_curr[i].inverse() * rel;
    const double dt_m = diff.translation().norm();
    const double dr_deg = Eigen::AngleAxisd(diff.rotation()).angle() * 180.0 / M_PI;
    EXPECT_LT(dt_m, 1e-3) << "pair " << i;
    EXPECT_LT(dr_deg, 0.01) << "pair " << i;
    // And the GT rows are not trivial: the car moves between scans.
    EXPECT_GT(rel.translation().norm(), 0.1) << "pair " << i;
    prev = curr;
  }
}

TEST(OxfordToBag, OptionsRenameTopicsAndFrames) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  ros::Time::init();
  const std::string path = tempBag("oxford_opts");
  ros_eval::OxfordBagOptions opt;
  opt.image_topic = "/navtech/polar";
  opt.fixed_frame = "map";
  opt.radar_frame = "navtech";
  std::string err;
  ASSERT_TRUE(ros_eval::writeOxfordBag(coral_data, path, opt, nullptr, &err)) << err;
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  std::size_t n = 0;
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery("/navtech/polar"))) {
    auto img = m.instantiate<sensor_msgs::Image>();
    ASSERT_TRUE(img);
    EXPECT_EQ(img->header.frame_id, "navtech");
    ++n;
  }
  EXPECT_EQ(n, 11u);
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery("/tf"))) {
    auto tf = m.instantiate<tf2_msgs::TFMessage>();
    ASSERT_TRUE(tf);
    EXPECT_EQ(tf->transforms[0].header.frame_id, "map");
    EXPECT_EQ(tf->transforms[0].child_frame_id, "navtech");
  }
  bag.close();
  std::remove(path.c_str());
}

TEST(OxfordToBag, BadInputGivesError) {
  ros::Time::init();
  std::string err;
  EXPECT_FALSE(ros_eval::writeOxfordBag("/nonexistent_folder", tempBag("none"),
                                        ros_eval::OxfordBagOptions(), nullptr, &err));
  EXPECT_NE(err.find("/nonexistent_folder"), std::string::npos) << err;
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  ros_eval::OxfordBagOptions opt;
  opt.radar_frame = "odom";  // same as the fixed frame
  EXPECT_FALSE(ros_eval::writeOxfordBag(coral_data, tempBag("bad"), opt, nullptr, &err));
  EXPECT_NE(err.find("frames"), std::string::npos) << err;
  EXPECT_FALSE(ros_eval::writeOxfordBag(coral_data, "/nonexistent_dir/x.bag",
                                        ros_eval::OxfordBagOptions(), nullptr, &err));
  EXPECT_NE(err.find("/nonexistent_dir/x.bag"), std::string::npos) << err;
}
