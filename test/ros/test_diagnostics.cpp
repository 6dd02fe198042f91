// CoralNodelet's diagnostics (no ROS master): overload, slow scans and TF failures are
// reported apart; a scan over the time budget is reported while it still runs; scans
// waiting for TF resolve once (duplicates too); header.seq gaps count lost scans; an input
// topic of another message type is an ERROR while it lasts.
#include <gtest/gtest.h>

#include "coral_introspection/AlignmentQuality.h"
#include "coral_introspection/ros/coral_diagnostics.hpp"
#include "coral_introspection/ros/coral_scan_source.hpp"

using coral_introspection::AlignmentQuality;
using namespace coral_introspection::ros_adapters;

namespace {

struct Report {
  std::string summary;
  int level = 0;
  std::map<std::string, std::string> values;
};

Report diagnose(Stats& s) {
  diagnostic_updater::DiagnosticStatusWrapper w;
  s.diagnose(w);
  Report r{w.message, w.level, {}};
  for (const auto& kv : w.values) r.values[kv.key] = kv.value;
  return r;
}

std_msgs::Header header(double stamp, uint32_t seq = 0) {
  std_msgs::Header h;
  h.stamp = ros::Time(stamp);
  h.frame_id = "lidar";
  h.seq = seq;
  return h;
}

class Diagnostics : public ::testing::Test {
 protected:
  void SetUp() override { ros::Time::init(); }
  coral_introspection::online::Counters counters_;
};

TEST_F(Diagnostics, DropsAndTfFailuresAreReportedApart) {
  Stats s;
  s.time_budget = 10.0;
  uint64_t dropped = 0;
  s.mailbox = [&] { return std::make_pair(dropped, uint64_t{0}); };
  WorkDone pair;
  pair.counters = &counters_;
  pair.status = AlignmentQuality::VERDICT;
  pair.seconds = 0.3;
  pair.latency = 0.35;
  s.finished(pair);
  WorkDone drop;
  drop.status = AlignmentQuality::DROPPED;
  drop.reason = "dropped";
  dropped = 3;
  s.finished(drop);
  Report r = diagnose(s);
  EXPECT_EQ(r.level, diagnostic_msgs::DiagnosticStatus::WARN);
  EXPECT_NE(r.summary.find("3 scan(s) dropped: worker busy (0.3 s per scan)"), std::string::npos)
      << r.summary;
  EXPECT_EQ(r.summary.find("TF"), std::string::npos) << r.summary;
  EXPECT_EQ(r.values["scans dropped (worker busy)"], "3");
  EXPECT_EQ(r.values["tf failures"], "0");
  EXPECT_EQ(r.values["processing time [s]"], "0.3");  // the drop notice is not a computation
  EXPECT_EQ(r.values["verdicts"], "1");

  ++counters_.pose_failures;
  WorkDone no_pose;
  no_pose.counters = &counters_;
  no_pose.status = AlignmentQuality::NO_POSE;
  no_pose.reason = "no transform odom <- 'lidar'";
  no_pose.problem = true;
  s.finished(no_pose);
  r = diagnose(s);
  EXPECT_EQ(r.summary, "1 TF failure(s): no transform odom <- 'lidar'");
  EXPECT_EQ(r.values["tf failures"], "1");
  EXPECT_EQ(r.values["last tf failure"], "no transform odom <- 'lidar'");
  r = diagnose(s);
  EXPECT_EQ(r.level, diagnostic_msgs::DiagnosticStatus::OK) << r.summary;
}

TEST_F(Diagnostics, ScanOverTimeBudgetIsReportedWhileItRuns) {
  Stats s;
  s.time_budget = 0.05;
  s.started(header(12.5));
  ros::WallDuration(0.1).sleep();
  Report r = diagnose(s);
  EXPECT_EQ(r.level, diagnostic_msgs::DiagnosticStatus::WARN);
  EXPECT_NE(r.summary.find("worker busy for"), std::string::npos) << r.summary;
  EXPECT_NE(r.summary.find("t = 12.5"), std::string::npos) << r.summary;
  s.mailbox = [] { return std::make_pair(uint64_t{4}, uint64_t{0}); };  // arriving meanwhile
  r = diagnose(s);
  EXPECT_NE(r.summary.find("4 scan(s) dropped: worker busy (on one scan for"), std::string::npos)
      << r.summary;
  EXPECT_EQ(r.values["scans dropped (worker busy)"], "4");
  WorkDone done;
  done.counters = &counters_;
  done.status = AlignmentQuality::VERDICT;
  done.seconds = 0.1;
  s.finished(done);
  r = diagnose(s);
  EXPECT_NE(r.summary.find("1 scan(s) over time_budget"), std::string::npos) << r.summary;
  EXPECT_EQ(r.values["scans over time budget"], "1");
  EXPECT_EQ(r.values["worker busy [s]"], "0");
  s.time_budget = 0.0;  // off: a long scan is no problem
  s.started(header(13.0));
  ros::WallDuration(0.06).sleep();
  EXPECT_EQ(diagnose(s).level, diagnostic_msgs::DiagnosticStatus::OK);
}

TEST_F(Diagnostics, PendingScansResolveOnceAndExpire) {
  Stats s;
  const std_msgs::Header h = header(5.0);
  s.waitForTf(h, ros::Time(100.0));
  s.waitForTf(h, ros::Time(101.0));  // the same stamp twice (a duplicate)
  ASSERT_TRUE(s.resolvePending(h));
  ASSERT_TRUE(s.resolvePending(h));
  EXPECT_FALSE(s.resolvePending(h)) << "a third resolve means a late scan";
  s.waitForTf(header(6.0), ros::Time(102.0));
  EXPECT_TRUE(s.expirePending(10.0).empty());
  ros::WallDuration(0.02).sleep();
  const auto expired = s.expirePending(0.01);
  ASSERT_EQ(expired.size(), 1u);
  EXPECT_EQ(expired[0].first.stamp, ros::Time(6.0));
  EXPECT_EQ(expired[0].second, ros::Time(102.0));  // the receipt time, for the latency
  EXPECT_FALSE(s.resolvePending(header(6.0)));
}

TEST_F(Diagnostics, SequenceGapsCountScansLostUpstream) {
  Stats s;
  s.arrived(header(1.0, 10), "/driver");
  s.arrived(header(1.1, 11), "/driver");
  s.arrived(header(1.4, 14), "/driver");  // 12 and 13 lost
  s.arrived(header(1.5, 0), "/other");
  Report r = diagnose(s);
  EXPECT_EQ(r.values["scans received"], "4");
  EXPECT_EQ(r.values["scans lost upstream (seq gaps)"], "2");
  EXPECT_NE(r.summary.find("2 scan(s) lost before the nodelet"), std::string::npos) << r.summary;
}

}  // namespace

// The input topic published with another message type: nothing can arrive, so every report
// is an ERROR led by why until the mismatch is gone (then OK again).
TEST_F(Diagnostics, InputTopicOfAnotherTypeIsAnErrorUntilGone) {
  const std::string polar_on_scan =
      inputTopicTypeError("/scan", "sensor_msgs/Image", InputType::kPointCloud);
  EXPECT_EQ(polar_on_scan,
            "input topic /scan carries sensor_msgs/Image, but this nodelet is configured for "
            "point clouds (input_type pointcloud) and reads sensor_msgs/PointCloud2 there: "
            "roscpp drops the connection, no scan arrives (remap scan to a PointCloud2 topic, "
            "or set input_type polar_image and remap polar_image)");
  EXPECT_NE(inputTopicTypeError("/polar_image", "sensor_msgs/PointCloud2", InputType::kPolarImage)
                .find("configured for polar radar images (input_type polar_image) and reads "
                      "sensor_msgs/Image there"),
            std::string::npos);
  EXPECT_EQ(inputTopicTypeError("/scan", "sensor_msgs/PointCloud2", InputType::kPointCloud), "");
  EXPECT_EQ(inputTopicTypeError("/polar_image", "sensor_msgs/Image", InputType::kPolarImage), "");
  EXPECT_EQ(inputTopicTypeError("/scan", "", InputType::kPointCloud), "");  // no publisher
  // LaserScan and PointCloud2 on `scan`: each nodelet names the input_type that reads the other.
  EXPECT_NE(inputTopicTypeError("/scan", "sensor_msgs/LaserScan", InputType::kPointCloud)
                .find("(set input_type laser_scan (and config/lidar_2d.yaml) for LaserScan)"),
            std::string::npos);
  EXPECT_NE(inputTopicTypeError("/scan", "sensor_msgs/PointCloud2", InputType::kLaserScan)
                .find("configured for laser scans (input_type laser_scan) and reads "
                      "sensor_msgs/LaserScan there: roscpp drops the connection, no scan arrives "
                      "(set input_type pointcloud for PointCloud2)"),
            std::string::npos);
  EXPECT_EQ(inputTopicTypeError("/scan", "sensor_msgs/LaserScan", InputType::kLaserScan), "");

  Stats s;
  s.inputTopicProblem(polar_on_scan);
  for (int report = 0; report < 2; ++report) {  // not only in the first report
    const Report r = diagnose(s);
    EXPECT_EQ(r.level, diagnostic_msgs::DiagnosticStatus::ERROR);
    EXPECT_EQ(r.summary, polar_on_scan);
  }
  s.inputTopicProblem("");
  const Report r = diagnose(s);
  EXPECT_EQ(r.level, diagnostic_msgs::DiagnosticStatus::OK) << r.summary;
}
