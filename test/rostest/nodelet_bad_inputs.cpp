// rostest: bad inputs never stop CoralNodelet (see nodelet_bad_inputs.test).
#include "coral_rostest_utils.hpp"
#include "rostest_main.hpp"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <limits>
#include <optional>

using namespace coral_test;
using coral_introspection::AlignmentQuality;

namespace {

class BadInputs : public ::testing::Test {
 protected:
  void SetUp() override { base_ = ros::Time::now(); }
  // Publishes TF (unless skip_tf) and msg at stamp.
  template <class M>
  void send(ros::Publisher& pub, M msg, const ros::Time& stamp, const std::string& frame,
            const Eigen::Isometry3d& T, bool skip_tf = false) {
    if (!skip_tf) sendTf(br_, T, stamp, frame);
    ros::WallDuration(0.03).sleep();
    msg.header.stamp = stamp;
    msg.header.frame_id = frame;
    pub.publish(msg);
    ros::WallDuration(0.05).sleep();
  }
  // Statuses of the nodelet `who` (e.g. "lidar/coral") from /diagnostics, latest last.
  std::map<std::string, std::string> diagnostics(const std::string& who, double timeout = 5.0) {
    std::map<std::string, std::string> values;
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
    diag_.clear();
    while (ros::WallTime::now() < end && values.empty()) {
      ros::WallDuration(0.1).sleep();
      for (const auto& arr : diag_.all())
        for (const auto& st : arr.status)
          if (st.name.find(who) != std::string::npos) {
            values.clear();
            for (const auto& kv : st.values) values[kv.key] = kv.value;
            values["__message"] = st.message;
            values["__level"] = std::to_string(st.level);
          }
    }
    return values;
  }

  ros::NodeHandle nh_;
  tf2_ros::TransformBroadcaster br_;
  ros::Time base_;
  std::mt19937 rng_{3};
  Collector<diagnostic_msgs::DiagnosticArray> diag_{nh_, "/diagnostics"};
};

TEST_F(BadInputs, CloudPathSurvivesAndCounts) {
  Collector<AlignmentQuality> verdicts(nh_, "/lidar/alignment");
  ros::Publisher pub = nh_.advertise<sensor_msgs::PointCloud2>("/lidar/scan", 10);
  ASSERT_TRUE(waitForSubscriber(pub));
  double t = 0.0;           // trajectory time of the next good scan
  ros::Time clock = base_;  // stamp of the next good scan
  auto good = [&]() {
    const Eigen::Isometry3d T = trajectory(t);
    send(pub, lidarCloud(T, clock, "lidar", rng_, 1), clock, "lidar", T);
    t += 0.1;
    clock += ros::Duration(0.1);
  };
  // One good scan then expect one more valid verdict.
  auto expectVerdict = [&](const char* after) {
    const std::size_t before = verdicts.size();
    good();
    ASSERT_TRUE(verdicts.waitFor(before + 1, 10.0)) << "no verdict after " << after;
    const AlignmentQuality m = verdicts.all().back();
    EXPECT_TRUE(m.valid) << after;
    EXPECT_TRUE(m.aligned) << after << " Q = " << m.quality;
  };
  good();
  expectVerdict("the first good pair");

  // Empty cloud (valid layout, zero points).
  sensor_msgs::PointCloud2 empty;
  sensor_msgs::PointCloud2Modifier(empty).setPointCloud2FieldsByString(1, "xyz");
  send(pub, empty, clock + ros::Duration(0.05), "lidar", trajectory(t - 0.05));
  expectVerdict("an empty cloud");

  // Only NaN / Inf points; then a good cloud with some NaN points mixed in.
  auto nan_cloud = lidarCloud(trajectory(t), clock, "lidar", rng_, 1);
  {
    sensor_msgs::PointCloud2Iterator<float> it(nan_cloud, "x");
    for (std::size_t i = 0; i < nan_cloud.width; ++i, ++it)
      it[i % 3] =
          i % 2 ? std::numeric_limits<float>::quiet_NaN() : std::numeric_limits<float>::infinity();
  }
  send(pub, nan_cloud, clock + ros::Duration(0.05), "lidar", trajectory(t - 0.05));
  {
    const std::size_t before = verdicts.size();
    const Eigen::Isometry3d T = trajectory(t);
    auto mixed = lidarCloud(T, clock, "lidar", rng_, 1);
    sensor_msgs::PointCloud2Iterator<float> it(mixed, "x");
    for (std::size_t i = 0; i < mixed.width; i += 10, it += 10) it[2] = std::nanf("");
    send(pub, mixed, clock, "lidar", T);
    t += 0.1;
    clock += ros::Duration(0.1);
    ASSERT_TRUE(verdicts.waitFor(before + 1, 10.0)) << "no verdict for a cloud with some NaN";
    EXPECT_TRUE(verdicts.all().back().valid);
  }
  expectVerdict("NaN / Inf clouds");

  // A cloud without z.
  sensor_msgs::PointCloud2 no_z;
  sensor_msgs::PointCloud2Modifier mod(no_z);
  mod.setPointCloud2Fields(3, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1,
                           sensor_msgs::PointField::FLOAT32, "intensity", 1,
                           sensor_msgs::PointField::FLOAT32);
  mod.resize(10);
  send(pub, no_z, clock + ros::Duration(0.05), "lidar", trajectory(t - 0.05));
  expectVerdict("a cloud without z");

  // Missing TF: far older than the TF buffer (extrapolation into the past), and a frame
  // nobody publishes (times out after tf_timeout = 0.5 s).
  send(pub, lidarCloud(trajectory(t), clock, "lidar", rng_, 1), base_ - ros::Duration(60.0),
       "lidar", trajectory(t), true);
  send(pub, lidarCloud(trajectory(t), clock, "lidar", rng_, 1), clock + ros::Duration(0.05),
       "ghost_frame", trajectory(t), true);
  ros::WallDuration(1.6).sleep();  // > tf_timeout + timer period
  expectVerdict("missing TF");

  // Time jumps backwards (looping bag): pairing restarts, no verdict for the jump itself.
  {
    const std::size_t before = verdicts.size();
    clock = base_ - ros::Duration(5.0);
    good();  // the reset scan
    ros::WallDuration(0.5).sleep();
    EXPECT_EQ(verdicts.size(), before) << "a scan after a time jump must not be paired";
  }
  expectVerdict("time jumping backwards");

  // Duplicate stamp: the same scan twice resets the pairing too.
  {
    const Eigen::Isometry3d T = trajectory(t - 0.1);
    const ros::Time last = clock - ros::Duration(0.1);
    const std::size_t before = verdicts.size();
    send(pub, lidarCloud(T, last, "lidar", rng_, 1), last, "lidar", T, true);
    ros::WallDuration(0.5).sleep();
    EXPECT_EQ(verdicts.size(), before) << "a duplicate stamp must not be paired";
  }
  expectVerdict("a duplicate stamp");

  const auto d = diagnostics("lidar/coral");
  ASSERT_FALSE(d.empty()) << "no diagnostics from lidar/coral";
  EXPECT_GE(std::stoul(d.at("bad inputs")), 3u);  // empty, all-NaN, no z
  EXPECT_GE(std::stoul(d.at("tf failures")), 2u);
  EXPECT_GE(std::stoul(d.at("non-finite points dropped")), 1u);
  EXPECT_GE(std::stoul(d.at("time jumps backwards")), 1u);
  EXPECT_GE(std::stoul(d.at("duplicate stamps")), 1u);
  EXPECT_GE(std::stoul(d.at("valid pairs")), 7u);
  EXPECT_EQ(std::stoul(d.at("callback errors")), 0u);
  EXPECT_EQ(std::stoul(d.at("misaligned pairs")), 0u);
}

TEST_F(BadInputs, ImagePathSurvivesWrongEncodingAndSize) {
  Collector<AlignmentQuality> verdicts(nh_, "/radar/alignment");
  ros::Publisher pub = nh_.advertise<sensor_msgs::Image>("/radar/polar_image", 10);
  ASSERT_TRUE(waitForSubscriber(pub));
  double t = 0.0;
  ros::Time clock = base_ + ros::Duration(0.013);  // distinct from the lidar test's stamps
  auto good = [&]() {
    send(pub, polarImage(trajectory, t, clock, "radar"), clock, "radar", trajectory(t));
    t += 0.25;
    clock += ros::Duration(0.25);
  };
  auto expectVerdict = [&](const char* after) {
    const std::size_t before = verdicts.size();
    good();
    ASSERT_TRUE(verdicts.waitFor(before + 1, 10.0)) << "no verdict after " << after;
    EXPECT_TRUE(verdicts.all().back().valid) << after;
    EXPECT_TRUE(verdicts.all().back().aligned) << after;
  };
  good();
  expectVerdict("the first good pair");
  auto rgb = polarImage(trajectory, t, clock, "radar");
  rgb.encoding = sensor_msgs::image_encodings::RGB8;
  send(pub, rgb, clock + ros::Duration(0.1), "radar", trajectory(t - 0.15));
  expectVerdict("an rgb8 image");
  auto small = polarImage(trajectory, t, clock, "radar", 300);  // 300 rows, 400 configured
  send(pub, small, clock + ros::Duration(0.1), "radar", trajectory(t - 0.15));
  expectVerdict("an image with the wrong number of azimuths");
  auto truncated = polarImage(trajectory, t, clock, "radar");
  truncated.data.resize(truncated.data.size() / 2);
  send(pub, truncated, clock + ros::Duration(0.1), "radar", trajectory(t - 0.15));
  expectVerdict("a truncated image");

  const auto d = diagnostics("radar/coral");
  ASSERT_FALSE(d.empty()) << "no diagnostics from radar/coral";
  EXPECT_GE(std::stoul(d.at("bad inputs")), 3u);
  EXPECT_EQ(std::stoul(d.at("callback errors")), 0u);
}

// Polar images published on the lidar nodelet's `scan`: roscpp drops every such connection
// before a callback, so the nodelet asks the master. It refuses the topic with one REFUSED
// notice (stamp 0: no scan) and reports an ERROR while that publisher exists; once it is
// gone, diagnostics recover and point clouds are judged again.
TEST_F(BadInputs, InputTopicOfAnotherTypeIsRefused) {
  Collector<AlignmentQuality> verdicts(nh_, "/lidar/alignment");
  Collector<AlignmentQuality> all(nh_, "/lidar/alignment", keepAll<AlignmentQuality>);
  const std::string why =
      "input topic /lidar/scan carries sensor_msgs/Image, but this nodelet is configured for "
      "point clouds (input_type pointcloud)";
  auto refusedNotice = [&]() -> std::optional<AlignmentQuality> {
    for (const AlignmentQuality& m : all.all())
      if (m.status == AlignmentQuality::REFUSED && m.reason.find(why) == 0) return m;
    return std::nullopt;
  };
  {
    ros::Publisher images = nh_.advertise<sensor_msgs::Image>("/lidar/scan", 1);
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(10.0);
    while (!refusedNotice() && ros::WallTime::now() < end) ros::WallDuration(0.1).sleep();
    const std::optional<AlignmentQuality> notice = refusedNotice();
    ASSERT_TRUE(notice) << "no REFUSED notice for images on /lidar/scan";
    EXPECT_TRUE(notice->stamp_b.isZero());
    EXPECT_FALSE(notice->valid);
    const auto d = diagnostics("lidar/coral");
    ASSERT_FALSE(d.empty());
    EXPECT_EQ(d.at("__level"), std::to_string(diagnostic_msgs::DiagnosticStatus::ERROR));
    EXPECT_EQ(d.at("__message").find(why), 0u) << d.at("__message");
    ros::WallDuration(1.5).sleep();  // later checks do not repeat the notice
    int notices = 0;
    for (const AlignmentQuality& m : all.all()) notices += m.reason.find(why) == 0;
    EXPECT_EQ(notices, 1);
  }
  // The image publisher is gone: no ERROR any more, and clouds give verdicts again.
  ros::Publisher pub = nh_.advertise<sensor_msgs::PointCloud2>("/lidar/scan", 10);
  ASSERT_TRUE(waitForSubscriber(pub));
  const std::size_t before = verdicts.size();
  ros::Time clock = ros::Time::now();
  for (int k = 0; k < 4; ++k, clock += ros::Duration(0.1)) {  // the first restarts the pairing
    const Eigen::Isometry3d T = trajectory(0.1 * k);
    send(pub, lidarCloud(T, clock, "lidar", rng_, 1), clock, "lidar", T);
  }
  ASSERT_TRUE(verdicts.waitFor(before + 2, 10.0));
  EXPECT_TRUE(verdicts.all().back().valid) << verdicts.all().back().reason;
  const auto d = diagnostics("lidar/coral");
  ASSERT_FALSE(d.empty());
  EXPECT_EQ(d.at("__message").find("input topic"), std::string::npos) << d.at("__message");
  EXPECT_EQ(std::stoul(d.at("callback errors")), 0u);
}

}  // namespace

// main(): test/rostest/rostest_main.cpp.
const coral_test::RostestNode coral_test::kRostestNode{"nodelet_bad_inputs_test", 2};
