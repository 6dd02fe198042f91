// Real data through the nodelet: the Oxford Radar RobotCar scans (../shared/data/
// oxford_radar_tiny) are converted to a rosbag (polar images + ground-truth TF), read back
// with the rosbag API and replayed into CoralNodelet (input_type polar_image, radar_oxford
// preset). With ground-truth TF every pair must be aligned; with lateral step errors in
// the TF (odometry that jumped), exactly the pairs that straddle a step must be flagged.
// Skips with a message when the data is absent.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Image.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/transform_broadcaster.h>

#include <unistd.h>
#include <cstdio>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "coral_introspection/AlignmentQuality.h"
#include "coral_introspection/ros/conversions.hpp"
#include "coral_introspection/ros_eval/oxford_bag_writer.hpp"
#include "coral_rostest_utils.hpp"
#include "rostest_main.hpp"
#include "support/test_data.hpp"

namespace ra = coral_introspection::ros_adapters;
namespace ros_eval = coral_introspection::ros_eval;
using coral_introspection::AlignmentQuality;

namespace {

struct ReplayScan {
  sensor_msgs::Image image;
  Eigen::Isometry3d T_odom_radar = Eigen::Isometry3d::Identity();
};

// Images of /radar/polar and the TF odom->radar at each image stamp, from the bag.
bool readBag(const std::string& path, std::vector<ReplayScan>* scans, std::string* error) {
  try {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    std::map<uint64_t, Eigen::Isometry3d> poses;
    std::vector<sensor_msgs::Image> images;
    for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
      if (auto img = m.instantiate<sensor_msgs::Image>(); img && m.getTopic() == "/radar/polar") {
        images.push_back(*img);
      } else if (auto tf = m.instantiate<tf2_msgs::TFMessage>()) {
        for (const auto& t : tf->transforms) {
          Eigen::Isometry3d T;
          std::string e;
          if (t.child_frame_id == "radar" && ra::toEigen(t.transform, &T, &e))
            poses[t.header.stamp.toNSec()] = T;
        }
      }
    }
    for (const auto& img : images) {
      const auto it = poses.find(img.header.stamp.toNSec());
      if (it == poses.end()) {
        *error = "no TF odom->radar at image stamp " + std::to_string(img.header.stamp.toSec());
        return false;
      }
      scans->push_back({img, it->second});
    }
  } catch (const std::exception& e) {
    *error = std::string("reading ") + path + ": " + e.what();
    return false;
  }
  return !scans->empty();
}

class Replayer {
 public:
  Replayer() {
    pub_ = nh_.advertise<sensor_msgs::Image>("/radar/polar", 20);  // the bag topic
  }
  bool connected() const {
    return pub_.getNumSubscribers() > 0 && verdicts_.sub().getNumPublishers() > 0;
  }

  // Publishes the TF of every scan (shifted by time_offset, poses by the injected error),
  // then the images one by one, each after the verdict of the previous one arrived.
  // Returns the verdicts by index of the later scan (scan 0 has none).
  std::map<int, AlignmentQuality> replay(const std::vector<ReplayScan>& scans,
                                         const std::vector<Eigen::Vector3d>& offsets,
                                         const ros::Duration& time_offset) {
    verdicts_.clear();
    std::vector<ros::Time> stamps;
    for (std::size_t i = 0; i < scans.size(); ++i) {
      stamps.push_back(scans[i].image.header.stamp + time_offset);
      geometry_msgs::TransformStamped t;
      t.header.stamp = stamps.back();
      t.header.frame_id = "odom";
      t.child_frame_id = scans[i].image.header.frame_id;
      t.transform = ra::toTransformMsg(Eigen::Translation3d(offsets[i]) * scans[i].T_odom_radar);
      tf_.sendTransform(t);
    }
    ros::WallDuration(0.5).sleep();  // the nodelet's TF listener has every pose first
    std::map<int, AlignmentQuality> out;
    for (std::size_t i = 0; i < scans.size(); ++i) {
      sensor_msgs::Image img = scans[i].image;
      img.header.stamp = stamps[i];
      pub_.publish(img);
      if (i == 0) {
        ros::WallDuration(0.3).sleep();  // first scan only becomes the reference
        continue;
      }
      AlignmentQuality v;
      if (verdicts_.waitFor(stamps[i], 10.0, &v)) out[static_cast<int>(i)] = v;
    }
    return out;
  }

 private:
  ros::NodeHandle nh_;
  ros::Publisher pub_;
  coral_test::VerdictsByStamp verdicts_{nh_, "alignment"};
  tf2_ros::TransformBroadcaster tf_;
};

void printVerdicts(const char* run, const std::map<int, AlignmentQuality>& v) {
  for (const auto& [i, m] : v)
    std::printf(
        "[oxford_replay] %s pair %d-%d: valid=%d aligned=%d p=%.3f H_joint=%.4f "
        "H_sep=%.4f Q=%.4f overlap=%.2f points=%u/%u\n",
        run, i - 1, i, m.valid, m.aligned, m.probability, m.h_joint, m.h_sep, m.quality, m.overlap,
        m.num_points_a, m.num_points_b);
  std::fflush(stdout);
}

TEST(OxfordReplay, GroundTruthAlignedAndStepErrorsFlagged) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  // 1. Convert with the package's converter (what `rosrun coral_introspection oxford_to_bag`
  // runs): /radar/polar raw Oxford images + /tf odom->radar from the ground truth.
  const std::string bag_path = coral_test::tempPath("coral_oxford_replay", ".bag");
  std::string error;
  ros_eval::OxfordBagSummary summary;
  ASSERT_TRUE(ros_eval::writeOxfordBag(coral_data, bag_path, ros_eval::OxfordBagOptions(), &summary,
                                       &error))
      << error;
  EXPECT_EQ(summary.images, 11u);
  std::vector<ReplayScan> scans;
  ASSERT_TRUE(readBag(bag_path, &scans, &error)) << error;
  std::remove(bag_path.c_str());
  ASSERT_EQ(scans.size(), 11u) << "oxford_radar_tiny holds 11 scans (10 pairs)";

  Replayer replayer;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ASSERT_TRUE(coral_test::waitUntil([&] { return replayer.connected(); }, 30.0))
      << "CoralNodelet did not connect to /radar/polar and alignment";

  // 2. Replay with ground-truth TF: all 10 pairs aligned.
  const std::vector<Eigen::Vector3d> zero(scans.size(), Eigen::Vector3d::Zero());
  const auto gt = replayer.replay(scans, zero, ros::Duration(0.0));
  printVerdicts("ground truth", gt);
  ASSERT_EQ(gt.size(), 10u) << "a verdict per consecutive pair";
  for (const auto& [i, m] : gt) {
    EXPECT_TRUE(m.valid) << "pair " << i - 1 << "-" << i;
    EXPECT_TRUE(m.aligned) << "pair " << i - 1 << "-" << i << " Q=" << m.quality;
  }

  // 3. Steps: from scan k on every pose is shifted 0.5 m laterally (sensor y at scan k),
  // signs alternating, as odometry that jumped. Only the straddling pairs are wrong.
  const std::set<int> steps = {3, 6, 8};
  std::vector<Eigen::Vector3d> offsets(scans.size(), Eigen::Vector3d::Zero());
  double sign = 1.0;
  for (int k : steps) {
    const Eigen::Vector3d jump =
        sign * 0.5 * (scans[k].T_odom_radar.linear() * Eigen::Vector3d::UnitY());
    for (std::size_t i = k; i < scans.size(); ++i) offsets[i] += jump;
    sign = -sign;
  }
  // Later stamps than run 1 (the TF buffer keeps the first run's poses; a looping bag
  // would instead jump back in time, which the nodelet also handles).
  const auto stepped = replayer.replay(scans, offsets, ros::Duration(100.0));
  printVerdicts("steps at 3,6,8", stepped);
  ASSERT_EQ(stepped.size(), 10u);
  for (const auto& [i, m] : stepped) {
    EXPECT_TRUE(m.valid) << "pair " << i - 1 << "-" << i;
    EXPECT_EQ(m.aligned, steps.count(i) == 0)
        << "pair " << i - 1 << "-" << i << (steps.count(i) ? " straddles a step" : " is clean")
        << " Q=" << m.quality << " p=" << m.probability;
  }
}

}  // namespace

// main(): test/rostest/rostest_main.cpp.
const coral_test::RostestNode coral_test::kRostestNode{"oxford_replay_test", 0};
