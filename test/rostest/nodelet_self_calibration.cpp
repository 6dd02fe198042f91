// Online self-calibration through the nodelet on real data: the Livox keyframes
// (../shared/data/hku1_livox_keyframes) are replayed into CoralNodelet (lidar_3d preset,
// method classifier) whose classifier is deliberately wrong (every pair "aligned"), with
// calibration/enabled. Every kStepEvery-th keyframe the odometry (TF) jumps by one tolerance
// (0.3 m along x or y, or 2 deg about yaw, in that keyframe's sensor frame), so exactly the
// pair straddling the jump is misaligned. Before calibration the wrong classifier misses the
// jumps; from pair kRightFrom on at least 95 % of the verdicts are right (the classifier's
// ceiling on these keyframes: a few jumps leave Q = H_joint - H_sep inside the clean pairs'
// range, doc/self_calibration.md). Diagnostics show the refit in use with its held-out AUC.
// Then the classifier YAML the nodelet wrote loads over the preset and judges held-back
// keyframes it never saw.
// Skips with a message when the data is absent.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/transform_broadcaster.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

#include "coral_introspection/AlignmentQuality.h"
#include "coral_introspection/eval/keyframe_sequence.hpp"
#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/ros/conversions.hpp"
#include "coral_introspection/ros/coral_params.hpp"
#include "coral_introspection/ros_eval/preset_file.hpp"
#include "coral_rostest_utils.hpp"
#include "rostest_main.hpp"
#include "support/test_data.hpp"

namespace coral = coral_introspection::coral;
namespace eval = coral_introspection::eval;
namespace ra = coral_introspection::ros_adapters;
namespace ros_eval = coral_introspection::ros_eval;
using coral_introspection::AlignmentQuality;

namespace {

constexpr int kScans = 161;     // keyframes replayed: 160 pairs
constexpr int kStepEvery = 8;   // odometry jump at keyframes 4, 12, 20, ...: 20 bad pairs
constexpr int kRightFrom = 20;  // stated: verdicts right (>= 95 %) from this pair on

bool isStep(int i) { return i % kStepEvery == kStepEvery / 2; }

// The jump at step keyframe i, in its sensor frame: x+, y+, yaw+, x-, y-, yaw- in turn.
Eigen::Isometry3d stepDelta(int i) {
  const int n = (i / kStepEvery) % 6;
  const double s = n < 3 ? 1.0 : -1.0;
  if (n % 3 == 2)
    return Eigen::Isometry3d(Eigen::AngleAxisd(s * 2.0 * M_PI / 180, Eigen::Vector3d::UnitZ()));
  return Eigen::Isometry3d(
      Eigen::Translation3d(n % 3 == 0 ? s * 0.3 : 0.0, n % 3 == 1 ? s * 0.3 : 0.0, 0.0));
}

class Replayer {
 public:
  Replayer() {
    pub_ = nh_.advertise<sensor_msgs::PointCloud2>("/livox/keyframes", 5);
    diag_ = nh_.subscribe("/diagnostics", 10, &Replayer::onDiagnostics, this);
  }
  // The latest value of a key of the nodelet's diagnostics ("" before the first report).
  std::string diagnostic(const std::string& key) {
    std::lock_guard<std::mutex> l(mu_);
    return diagnostics_.count(key) ? diagnostics_[key] : "";
  }
  bool connected() const {
    return pub_.getNumSubscribers() > 0 && verdicts_.sub().getNumPublishers() > 0;
  }

  // TF odom->livox at the stamp, then the cloud; waits for its AlignmentQuality.
  bool send(const coral::Points& points, const Eigen::Isometry3d& T_odom_livox,
            const ros::Time& stamp, AlignmentQuality* out) {
    geometry_msgs::TransformStamped t;
    t.header.stamp = stamp;
    t.header.frame_id = "odom";
    t.child_frame_id = "livox";
    t.transform = ra::toTransformMsg(T_odom_livox);
    tf_.sendTransform(t);
    ros::WallDuration(0.02).sleep();  // TF first: no wait in the nodelet's message filter
    std_msgs::Header h;
    h.stamp = stamp;
    h.frame_id = "livox";
    pub_.publish(ra::pointsToCloud(points, h));
    return verdicts_.waitFor(stamp, 30.0, out);
  }

 private:
  void onDiagnostics(const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mu_);
    for (const auto& st : m->status)
      if (st.name.find("CorAl alignment") != std::string::npos)
        for (const auto& kv : st.values) diagnostics_[kv.key] = kv.value;
  }
  ros::NodeHandle nh_;
  ros::Publisher pub_;
  coral_test::VerdictsByStamp verdicts_{nh_, "alignment"};
  ros::Subscriber diag_;
  std::map<std::string, std::string> diagnostics_;
  tf2_ros::TransformBroadcaster tf_;
  std::mutex mu_;
};

TEST(NodeletSelfCalibration, WrongClassifierBecomesRightOnLivoxKeyframes) {
  CORAL_REQUIRE_DATA("hku1_livox_keyframes");
  eval::KeyframeSequenceConfig kc;
  kc.max_scans = 0;
  std::vector<eval::TrainingScan> scans;
  coral::Isometries T_world;
  std::string error;
  ASSERT_TRUE(eval::loadKeyframeSequence(coral_data, kc, {}, &scans, &T_world, &error)) << error;
  ASSERT_GE(scans.size(), static_cast<std::size_t>(kScans + 20));

  Replayer replayer;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ASSERT_TRUE(coral_test::waitUntil([&] { return replayer.connected(); }, 30.0))
      << "CoralNodelet did not connect";

  // Odometry with jumps: T'_i = C_i T_i, C_i = C_{i-1} T_i Delta_i T_i^-1 at a step, so the
  // straddling pair's relative pose is off by Delta_i (in i's frame) and every other is exact.
  Eigen::Isometry3d C = Eigen::Isometry3d::Identity();
  int wrong_early = 0, missed_early = 0, right_late = 0, wrong_late = 0;
  int jumps_late = 0, flagged_late = 0, false_alarms_late = 0;
  for (int i = 0; i < kScans; ++i) {
    if (isStep(i)) C = C * T_world[i] * stepDelta(i) * T_world[i].inverse();
    AlignmentQuality m;
    const ros::Time stamp(1000.0 + 0.5 * i);
    ASSERT_TRUE(replayer.send(scans[i].scan.points, C * T_world[i], stamp, &m)) << "scan " << i;
    if (i == 0) continue;
    ASSERT_TRUE(m.valid) << "pair " << i - 1 << "-" << i << ": " << m.reason;
    const bool right = m.aligned != isStep(i);
    std::printf("[self_calibration] pair %d-%d %s: aligned=%d p=%.3f Q=%.4f %s\n", i - 1, i,
                isStep(i) ? "STEP " : "clean", m.aligned, m.probability, m.quality,
                right ? "" : "WRONG");
    if (i < kRightFrom) {
      wrong_early += !right;
      missed_early += isStep(i) && m.aligned;
    } else {
      wrong_late += !right;
      right_late += right;
      jumps_late += isStep(i);
      flagged_late += isStep(i) && !m.aligned;
      false_alarms_late += !isStep(i) && !m.aligned;
    }
  }
  std::printf(
      "[self_calibration] pairs 1-%d: %d wrong (%d jumps missed); pairs %d-%d: %d right, %d "
      "wrong, %d of %d jumps flagged, %d false alarms\n",
      kRightFrom - 1, wrong_early, missed_early, kRightFrom, kScans - 1, right_late, wrong_late,
      flagged_late, jumps_late, false_alarms_late);
  std::fflush(stdout);
  EXPECT_GE(missed_early, 1) << "the wrong classifier must miss jumps before calibration";
  EXPECT_GE(right_late, 0.95 * (right_late + wrong_late));
  EXPECT_GE(flagged_late, 0.75 * jumps_late);  // the wrong classifier flags none
  EXPECT_LE(false_alarms_late, 2);

  // Diagnostics (1 Hz): the refit judges, with its held-out AUC; samples within the bound.
  ros::WallDuration(2.5).sleep();
  std::printf(
      "[self_calibration] diagnostics: in use %s, held-out AUC %s, samples %s, refits %s, "
      "accepted %s of %s pairs\n",
      replayer.diagnostic("calibration in use").c_str(),
      replayer.diagnostic("calibration held-out AUC").c_str(),
      replayer.diagnostic("calibration samples").c_str(),
      replayer.diagnostic("calibration refits").c_str(),
      replayer.diagnostic("calibration pairs accepted").c_str(),
      replayer.diagnostic("calibration pairs selected").c_str());
  EXPECT_EQ(replayer.diagnostic("calibration in use"), "true");
  EXPECT_GE(std::atof(replayer.diagnostic("calibration held-out AUC").c_str()), 0.9);
  EXPECT_LE(std::atoi(replayer.diagnostic("calibration samples").c_str()), 2000);
  EXPECT_EQ(replayer.diagnostic("calibration pairs selected"), std::to_string(kScans - 1));

  // The classifier file the nodelet wrote loads over the preset (method classifier) and
  // judges keyframes it never saw: at the optimized poses aligned, one tolerance off not.
  ros::NodeHandle pnh("~");
  std::string file;
  ASSERT_TRUE(pnh.getParam("calibration_file", file));
  ra::NodeConfig cfg;
  ASSERT_TRUE(ros_eval::loadPresetFiles({coral_test::sourceDir() + "/config/lidar_3d.yaml", file},
                                        &cfg, &error))
      << error;
  EXPECT_EQ(cfg.online.verdict.method, coral::VerdictMethod::kClassifier);
  EXPECT_LT(cfg.online.verdict.classifier.beta0, 30.0);  // not the wrong starting point
  int right = 0, total = 0;
  for (int i = kScans + 5; i < kScans + 20; ++i) {
    const Eigen::Isometry3d T = T_world[i - 1].inverse() * T_world[i];
    const auto at_truth = coral_introspection::online::judgePair(scans[i - 1].scan, scans[i].scan,
                                                                 T, cfg.online, false);
    const auto off = coral_introspection::online::judgePair(scans[i - 1].scan, scans[i].scan,
                                                            T * stepDelta(i), cfg.online, false);
    right += at_truth.verdict.valid && at_truth.verdict.aligned;
    right += off.verdict.valid && !off.verdict.aligned;
    total += 2;
    std::printf("[self_calibration] held back %d-%d: truth p=%.3f, off p=%.3f\n", i - 1, i,
                at_truth.verdict.probability, off.verdict.probability);
  }
  std::printf("[self_calibration] written classifier on keyframes %d-%d: %d of %d right\n",
              kScans + 4, kScans + 19, right, total);
  EXPECT_GE(right, 0.8 * total);  // the classifier's in-data-set accuracy on hku1 is 0.90
}

}  // namespace

// main(): test/rostest/rostest_main.cpp.
const coral_test::RostestNode coral_test::kRostestNode{"nodelet_self_calibration_test", 0};
