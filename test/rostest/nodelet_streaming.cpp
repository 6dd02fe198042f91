// rostest: CoralNodelet under overload, with a slow pair, a looping sequence and scans that
// cannot be judged (see nodelet_streaming.test).
#include "coral_rostest_utils.hpp"
#include "rostest_main.hpp"

#include <sensor_msgs/point_cloud2_iterator.h>

#include "coral_introspection/CheckAlignment.h"
#include "coral_introspection/ros_eval/stream_bench.hpp"

using namespace coral_test;
using coral_introspection::AlignmentQuality;
namespace ra = coral_introspection::ros_adapters;
namespace ros_eval = coral_introspection::ros_eval;

namespace {

unsigned long value(const std::map<std::string, std::string>& d, const std::string& key) {
  const auto it = d.find(key);
  return it == d.end() ? 0ul : std::stoul(it->second);
}

class Streaming : public ::testing::Test {
 protected:
  // One scan of the 1-ring yard at trajectory time t, stamped `stamp`, TF first.
  void scan(ros::Publisher& pub, const std::string& frame, double t, const ros::Time& stamp,
            bool with_tf = true) {
    if (with_tf) sendTf(br_, trajectory(t), stamp, frame);
    ros::WallDuration(0.03).sleep();
    pub.publish(lidarCloud(trajectory(t), stamp, frame, rng_, 1));
    ros::WallDuration(0.1).sleep();
  }
  // The message of the scan stamped `stamp` (waits for it).
  std::optional<AlignmentQuality> messageOf(Collector<AlignmentQuality>& c, const ros::Time& stamp,
                                            double timeout = 5.0) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
    while (ros::WallTime::now() < end) {
      for (const auto& m : c.all())
        if (m.stamp_b == stamp) return m;
      ros::WallDuration(0.02).sleep();
    }
    return std::nullopt;
  }

  ros::NodeHandle nh_;
  tf2_ros::TransformBroadcaster br_;
  std::mt19937 rng_{5};
};

// 3x overload: ~10 pairs/s possible, 30 scans/s offered. The newest scan wins: older
// unjudged scans are dropped (each with a DROPPED message, counted), latency stays bounded,
// diagnostics name the drops and do not blame TF.
TEST_F(Streaming, OverloadDropsOldestScansAndSaysSo) {
  ros_eval::VerdictMonitor monitor(nh_, "/stream/alignment", "stream/coral");
  std::mt19937 rng(1);
  eval::LidarModel m;
  m.rings = 1;
  m.v_min_deg = m.v_max_deg = 0.0;
  const coral::Points world = eval::simulateScan(eval::SyntheticScene::structuredYard(),
                                                 Eigen::Isometry3d::Identity(), m, rng);
  ros_eval::StreamOptions opt;
  opt.topic = "/stream/scan";
  opt.frame = "stream_lidar";
  opt.rate = 30.0;
  opt.speed = 3.0;
  ros_eval::CloudStreamer streamer(nh_, world, opt);
  ASSERT_TRUE(streamer.waitForSubscriber(15.0));
  ros::WallDuration(1.0).sleep();  // TF connections
  monitor.reset();
  const std::size_t sent = streamer.run(3.0);
  ASSERT_TRUE(monitor.waitFor(sent, 10.0)) << monitor.size() << " messages for " << sent;
  ros::WallDuration(1.5).sleep();  // one more diagnostics report
  const ros_eval::StreamSummary s = monitor.summary();
  EXPECT_EQ(s.messages, sent) << "one message per scan";
  EXPECT_EQ(s.without_reason, 0u) << "every message without a verdict says why";
  const std::size_t dropped =
      s.by_status.count(AlignmentQuality::DROPPED) ? s.by_status.at(AlignmentQuality::DROPPED) : 0;
  EXPECT_GE(dropped, sent / 3) << "at most ~1/3 can be judged";
  EXPECT_GE(s.verdicts, 10u);
  EXPECT_EQ(s.by_status.count(AlignmentQuality::NO_POSE), 0u) << "TF is never blamed";
  // Newest wins: no scan waits behind a queue of older ones (the old subscriber queue let
  // latency grow to many seconds).
  EXPECT_LT(s.latency_max, 1.5);

  const auto d = monitor.diagnostics();
  ASSERT_FALSE(d.empty()) << "no diagnostics from stream/coral";
  EXPECT_EQ(value(d, "scans dropped (worker busy)"), dropped);
  EXPECT_EQ(value(d, "tf failures"), 0u);
  EXPECT_EQ(value(d, "late scans (TF after tf_timeout)"), 0u);
  EXPECT_EQ(value(d, "scans received"), sent);
  bool said = false;
  for (const auto& msg : monitor.diagnosticMessages()) {
    if (msg.find("dropped: worker busy") != std::string::npos) said = true;
    EXPECT_EQ(msg.find("TF failure"), std::string::npos) << msg;
  }
  EXPECT_TRUE(said) << "no diagnostics message mentioned the dropped scans";
}

// While the worker spends 10 s on a pair, check_alignment and /diagnostics answer within
// 1 s, and the pair is reported as over the time budget while it still runs.
TEST_F(Streaming, ServiceAndDiagnosticsAnswerWhileAPairRuns) {
  ros_eval::VerdictMonitor monitor(nh_, "/slow/alignment", "slow/coral");
  ros::Publisher pub = nh_.advertise<sensor_msgs::PointCloud2>("/slow/scan", 10);
  ASSERT_TRUE(waitForSubscriber(pub));
  ros::WallDuration(1.0).sleep();
  const ros::Time base = ros::Time::now();
  scan(pub, "slow_lidar", 0.0, base);
  scan(pub, "slow_lidar", 0.1, base + ros::Duration(0.1));  // the 10 s pair
  ros::WallDuration(0.5).sleep();
  monitor.reset();
  const ros::WallTime busy_from = ros::WallTime::now();

  coral_introspection::CheckAlignment srv;
  srv.request.cloud_a = lidarCloud(trajectory(0.0), base, "a", rng_, 1);
  srv.request.cloud_b = lidarCloud(trajectory(0.2), base, "b", rng_, 1);
  srv.request.transform_a_b =
      ra::toTransformMsg(trajectory(0.0).inverse() * trajectory(0.2));  // correct
  for (int i = 0; i < 3; ++i) {
    const ros::WallTime t0 = ros::WallTime::now();
    ASSERT_TRUE(ros::service::call("/slow/check_alignment", srv));
    const double took = (ros::WallTime::now() - t0).toSec();
    EXPECT_LT(took, 1.0) << "check_alignment waited for the worker";
    EXPECT_EQ(srv.response.error, "");
    EXPECT_TRUE(srv.response.result.aligned);
    ros::WallDuration(0.5).sleep();
  }
  // Diagnostics keep coming (1 Hz) and, past time_budget = 2 s, name the busy worker.
  ros::WallDuration(3.5 - (ros::WallTime::now() - busy_from).toSec()).sleep();
  const auto during = monitor.diagnosticMessages();
  EXPECT_GE(during.size(), 3u) << "diagnostics went silent while the pair ran";
  bool warned = false;
  for (const auto& m : during)
    if (m.find("worker busy for") != std::string::npos) warned = true;
  EXPECT_TRUE(warned) << "no diagnostics named the pair over time_budget";
  EXPECT_EQ(monitor.summary().verdicts, 0u) << "the slow pair cannot be done yet";
  // The pair completes and is counted as over budget.
  ASSERT_TRUE(monitor.waitFor(1, 12.0));
  ros::WallDuration(1.2).sleep();
  EXPECT_GE(value(monitor.diagnostics(), "scans over time budget"), 1u);
}

// A short sequence published twice, the second time 100 s earlier (a looping bag without
// --clock: longer than tf2's 10 s cache, so the replayed TF would be refused as too old):
// the second loop's first pair is judged. The second loop's first transform overtakes the
// first loop's last scan (as in `rosbag play -l`: a scan message is larger than a
// transform): that scan is still judged, with its pose from before the jump.
TEST_F(Streaming, LoopingSequenceIsJudgedFromItsFirstPair) {
  Collector<AlignmentQuality> all(nh_, "/lidar/alignment", keepAll<AlignmentQuality>);
  ros::Publisher pub = nh_.advertise<sensor_msgs::PointCloud2>("/lidar/scan", 10);
  ASSERT_TRUE(waitForSubscriber(pub));
  ros::WallDuration(1.0).sleep();
  const ros::Time now = ros::Time::now();
  std::vector<std::vector<ros::Time>> loops(2);
  for (int k = 0; k < 4; ++k) {
    loops[0].push_back(now + ros::Duration(-50.0 + 0.1 * k));
    loops[1].push_back(now + ros::Duration(-150.0 + 0.1 * k));
  }
  for (int k = 0; k < 3; ++k) scan(pub, "loop_lidar", 0.1 * k, loops[0][k]);
  sendTf(br_, trajectory(0.3), loops[0][3], "loop_lidar");
  ros::WallDuration(0.03).sleep();
  sendTf(br_, trajectory(0.0), loops[1][0], "loop_lidar");  // the next loop's first TF
  ros::WallDuration(0.1).sleep();
  pub.publish(lidarCloud(trajectory(0.3), loops[0][3], "loop_lidar", rng_, 1));
  ros::WallDuration(0.1).sleep();
  pub.publish(lidarCloud(trajectory(0.0), loops[1][0], "loop_lidar", rng_, 1));
  ros::WallDuration(0.1).sleep();
  for (int k = 1; k < 4; ++k) scan(pub, "loop_lidar", 0.1 * k, loops[1][k]);

  for (const auto& stamps : loops) {
    const double loop_start = (stamps[0] - now).toSec();
    const auto first = messageOf(all, stamps[0]);
    ASSERT_TRUE(first) << "loop at " << loop_start;
    EXPECT_EQ(first->status, AlignmentQuality::NOT_PAIRED) << first->reason;
    for (int k = 1; k < 4; ++k) {
      const auto m = messageOf(all, stamps[k]);
      ASSERT_TRUE(m) << "loop at " << loop_start << ", scan " << k;
      EXPECT_EQ(m->status, AlignmentQuality::VERDICT)
          << "loop at " << loop_start << ", scan " << k << ": " << m->reason;
      EXPECT_TRUE(m->aligned) << "loop at " << loop_start << ", scan " << k;
      EXPECT_EQ(m->stamp_a, stamps[k - 1]);
    }
  }
  ros::WallDuration(1.2).sleep();
  Collector<diagnostic_msgs::DiagnosticArray> diag(nh_, "/diagnostics");
  ASSERT_TRUE(diag.waitFor(3, 5.0));
  unsigned long clears = 0, tf_failures = 0;
  for (const auto& a : diag.all())
    for (const auto& st : a.status)
      if (st.name.find("lidar/coral") != std::string::npos)
        for (const auto& kv : st.values) {
          if (kv.key == "tf buffer clears") clears = std::stoul(kv.value);
          if (kv.key == "tf failures") tf_failures = std::stoul(kv.value);
        }
  EXPECT_GE(clears, 1u);
  EXPECT_EQ(tf_failures, 0u);
}

// A scan stamped 0 is refused with a reason and does not cost the next pair.
TEST_F(Streaming, UnstampedScanIsRefusedAndTheNextPairJudged) {
  Collector<AlignmentQuality> all(nh_, "/lidar/alignment", keepAll<AlignmentQuality>);
  ros::Publisher pub = nh_.advertise<sensor_msgs::PointCloud2>("/lidar/scan", 10);
  ASSERT_TRUE(waitForSubscriber(pub));
  ros::WallDuration(1.0).sleep();
  const ros::Time a = ros::Time::now(), b = a + ros::Duration(0.2);
  scan(pub, "s0_lidar", 0.0, a);
  scan(pub, "s0_lidar", 0.1, ros::Time(), false);
  scan(pub, "s0_lidar", 0.2, b);
  const auto refused = messageOf(all, ros::Time());
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->status, AlignmentQuality::REFUSED);
  EXPECT_NE(refused->reason.find("stamp is 0"), std::string::npos) << refused->reason;
  const auto next = messageOf(all, b);
  ASSERT_TRUE(next);
  EXPECT_EQ(next->status, AlignmentQuality::VERDICT) << next->reason;
  EXPECT_EQ(next->stamp_a, a);
  EXPECT_TRUE(next->aligned);
  // Counted and named in diagnostics too.
  ros_eval::VerdictMonitor monitor(nh_, "/lidar/alignment", "lidar/coral");
  ros::WallDuration(2.2).sleep();
  const auto d = monitor.diagnostics();
  EXPECT_EQ(value(d, "unstamped scans refused"), 1u);
  ASSERT_TRUE(d.count("last error"));
  EXPECT_NE(d.at("last error").find("stamp is 0"), std::string::npos) << d.at("last error");
}

// TF arriving after tf_timeout: the scan was reported (NO_POSE, tf failure) and is not
// judged later; the next scan pairs with the last judged one and the late scan is counted.
TEST_F(Streaming, LateTfIsAFailureAndNotJudgedLater) {
  Collector<AlignmentQuality> all(nh_, "/lidar/alignment", keepAll<AlignmentQuality>);
  ros::Publisher pub = nh_.advertise<sensor_msgs::PointCloud2>("/lidar/scan", 10);
  ASSERT_TRUE(waitForSubscriber(pub));
  ros::WallDuration(1.0).sleep();
  const ros::Time a = ros::Time::now();
  const ros::Time late = a + ros::Duration(0.1), b = a + ros::Duration(0.2);
  scan(pub, "late_lidar", 0.0, a);
  scan(pub, "late_lidar", 0.1, late, false);
  const auto failed = messageOf(all, late, 3.0);  // tf_timeout 0.3 s + timer period
  ASSERT_TRUE(failed);
  EXPECT_EQ(failed->status, AlignmentQuality::NO_POSE);
  EXPECT_NE(failed->reason.find("tf_timeout"), std::string::npos) << failed->reason;
  sendTf(br_, trajectory(0.1), late, "late_lidar");  // now it comes
  scan(pub, "late_lidar", 0.2, b);
  const auto next = messageOf(all, b);
  ASSERT_TRUE(next);
  EXPECT_EQ(next->status, AlignmentQuality::VERDICT) << next->reason;
  EXPECT_EQ(next->stamp_a, a) << "the late scan must not become the reference";
  ros::WallDuration(0.5).sleep();
  std::size_t of_late = 0;
  for (const auto& m : all.all()) of_late += m.stamp_b == late ? 1 : 0;
  EXPECT_EQ(of_late, 1u) << "the late scan got a second message";
  ros_eval::VerdictMonitor monitor(nh_, "/lidar/alignment", "lidar/coral");
  ros::WallDuration(2.2).sleep();
  EXPECT_EQ(value(monitor.diagnostics(), "late scans (TF after tf_timeout)"), 1u);
}

// Integer point fields are refused with the field and its type in the reason.
TEST_F(Streaming, IntegerPointFieldsAreRefused) {
  Collector<AlignmentQuality> all(nh_, "/lidar/alignment", keepAll<AlignmentQuality>);
  ros::Publisher pub = nh_.advertise<sensor_msgs::PointCloud2>("/lidar/scan", 10);
  ASSERT_TRUE(waitForSubscriber(pub));
  ros::WallDuration(1.0).sleep();
  sensor_msgs::PointCloud2 c;
  sensor_msgs::PointCloud2Modifier mod(c);
  mod.setPointCloud2Fields(3, "x", 1, sensor_msgs::PointField::INT16, "y", 1,
                           sensor_msgs::PointField::INT16, "z", 1, sensor_msgs::PointField::INT16);
  mod.resize(100);
  const ros::Time stamp = ros::Time::now();
  c.header.stamp = stamp;
  c.header.frame_id = "int_lidar";
  sendTf(br_, trajectory(0.0), stamp, "int_lidar");
  ros::WallDuration(0.05).sleep();
  pub.publish(c);
  const auto m = messageOf(all, stamp);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->status, AlignmentQuality::REFUSED);
  EXPECT_NE(m->reason.find("field 'x' is int16"), std::string::npos) << m->reason;
  ros_eval::VerdictMonitor monitor(nh_, "/lidar/alignment", "lidar/coral");
  ros::WallDuration(2.2).sleep();
  const auto d = monitor.diagnostics();
  EXPECT_GE(value(d, "bad inputs"), 1u);
  ASSERT_TRUE(d.count("last no-verdict reason"));
  EXPECT_NE(d.at("last no-verdict reason").find("field 'x' is int16"), std::string::npos)
      << d.at("last no-verdict reason");
}

}  // namespace

// main(): test/rostest/rostest_main.cpp.
const coral_test::RostestNode coral_test::kRostestNode{"nodelet_streaming_test", 3};
