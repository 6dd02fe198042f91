// RioNodelet on the TI mmWave bag (odometry, covariance, TF, the loop closes; played twice in
// a row: every loop tracked), on bad
// inputs (diagnostics count them, the odometry recovers, the nodelet survives), on input it
// must refuse (ERROR diagnostics, no odometry), with bad configs (the load fails), and with
// the barometer on (subscribed, used).
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/FluidPressure.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <std_msgs/Header.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <topic_tools/shape_shifter.h>

#include <cmath>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <nodelet/NodeletList.h>
#include <nodelet/NodeletLoad.h>
#include <nodelet/NodeletUnload.h>

#include <algorithm>
#include <fstream>

#include "rostest_main.hpp"
#include "support/test_data.hpp"

namespace {

struct Collector {
  std::mutex m;
  std::vector<nav_msgs::Odometry> odom;
  std::map<std::string, std::string> diag;  // key -> value of the `name` status
  std::string summary;
  int level = -1;
  long diag_updates = 0;
};

void waitFor(ros::NodeHandle& nh, const ros::Publisher& p) {
  for (int i = 0; i < 100 && p.getNumSubscribers() == 0; ++i) ros::WallDuration(0.05).sleep();
  (void)nh;
}

long diagValue(Collector& c, const std::string& key) {
  std::lock_guard<std::mutex> l(c.m);
  auto it = c.diag.find(key);
  return it == c.diag.end() ? -1 : std::stol(it->second);
}

ros::Subscriber diagnosticsOf(ros::NodeHandle& nh, const std::string& name, Collector* c) {
  return nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 50, [c, name](const diagnostic_msgs::DiagnosticArrayConstPtr& msg) {
        for (const auto& s : msg->status) {
          if (s.name.find(name) == std::string::npos) continue;
          std::lock_guard<std::mutex> l(c->m);
          for (const auto& kv : s.values) c->diag[kv.key] = kv.value;
          c->summary = s.message;
          c->level = s.level;
          ++c->diag_updates;
        }
      });
}

ros::Subscriber odometryOf(ros::NodeHandle& nh, const std::string& topic, Collector* c) {
  return nh.subscribe<nav_msgs::Odometry>(topic, 1000, [c](const nav_msgs::OdometryConstPtr& m) {
    std::lock_guard<std::mutex> l(c->m);
    c->odom.push_back(*m);
  });
}

// The IMU, radar, trigger and barometer messages of the TI bag `bag_file` into the nodelet of
// namespace `ns`, `loops` times in a row (as `rosbag play -l`: the stamps and sequence numbers
// start over), in bag order, 5x faster than recorded (the estimator needs ~2 ms per radar
// frame).
// Published as raw bytes, as `rosbag play` does: a typed roscpp publisher rewrites
// header.seq, and the radar scans are paired with their triggers by seq. Needs a spinner.
void playTiBag(ros::NodeHandle& nh, const std::string& bag_file, const std::string& ns, int loops) {
  rosbag::Bag bag;
  bag.open(bag_file, rosbag::bagmode::Read);
  const std::map<std::string, std::string> remap = {
      {"/sensor_platform/imu", ns + "/imu"},
      {"/ti_mmwave/radar_scan_pcl", ns + "/radar"},
      {"/sensor_platform/radar_right/trigger", ns + "/trigger"},
      {"/sensor_platform/baro", ns + "/baro"}};
  rosbag::View view(
      bag, rosbag::TopicQuery({"/sensor_platform/imu", "/ti_mmwave/radar_scan_pcl",
                               "/sensor_platform/radar_right/trigger", "/sensor_platform/baro"}));
  std::map<std::string, ros::Publisher> pubs;
  for (const rosbag::ConnectionInfo* ci : view.getConnections()) {
    if (pubs.count(ci->topic)) continue;
    ros::AdvertiseOptions opts(remap.at(ci->topic), 5000, ci->md5sum, ci->datatype, ci->msg_def);
    pubs[ci->topic] = nh.advertise(opts);
  }
  ASSERT_EQ(pubs.size(), 4u) << "the bag lacks one of the imu, radar, trigger and baro topics";
  for (auto& p : pubs) waitFor(nh, p.second);
  for (int loop = 0; loop < loops; ++loop) {
    ros::Time last;
    for (const rosbag::MessageInstance& m : view) {
      if (!last.isZero() && m.getTime() > last)
        ros::WallDuration((m.getTime() - last).toSec() / 5).sleep();
      last = m.getTime();
      pubs[m.getTopic()].publish(*m.instantiate<topic_tools::ShapeShifter>());
    }
  }
  ros::WallDuration(1.5).sleep();
}

}  // namespace

TEST(RioNodelet, TiBagGivesOdometryCovarianceTfAndClosesTheLoop) {
  CORAL_REQUIRE_DATA("ti_mmwave_demo");
  ros::NodeHandle nh;
  Collector c;
  ros::Subscriber so = odometryOf(nh, "/ti/odometry", &c);
  ros::Subscriber sd = diagnosticsOf(nh, "rio_ti", &c);
  tf2_ros::Buffer tf(ros::Duration(100.0));
  tf2_ros::TransformListener listener(tf);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  playTiBag(nh, coral_data + "/ti_mmwave_rospkg_demo.bag", "/ti", 1);
  std::lock_guard<std::mutex> l(c.m);
  // 412 scans; about 1 s of standing start initialises the filter.
  ASSERT_GE(c.odom.size(), 350u) << "diagnostics: imu " << c.diag["imu messages"] << ", radar "
                                 << c.diag["radar messages"] << ", triggers "
                                 << c.diag["trigger messages"] << ", frames " << c.diag["frames"]
                                 << ", " << c.summary;
  const nav_msgs::Odometry& first = c.odom.front();
  const nav_msgs::Odometry& end = c.odom.back();
  // A frame whose window solve gave no covariance says so (pose.covariance[0] = -1, REP 145
  // "unknown"); that may happen right after initialisation, not as a habit.
  std::size_t unknown_covariance = 0;
  for (const nav_msgs::Odometry& o : c.odom) {
    EXPECT_EQ(o.header.frame_id, "odom");
    EXPECT_EQ(o.child_frame_id, "base_link");
    if (o.pose.covariance[0] == -1.0) {
      ++unknown_covariance;
      continue;
    }
    for (int i = 0; i < 6; ++i) {
      EXPECT_TRUE(std::isfinite(o.pose.covariance[7 * i]));
      EXPECT_GT(o.pose.covariance[7 * i], 0.0) << "pose covariance diagonal " << i;
    }
  }
  EXPECT_LE(unknown_covariance, 3u);
  // Hand-held loop: ends where it started (offline runner: 0.053 m, height +0.073 m with the
  // barometer of the shipped config; the nodelet gets the same data, so a loose bound catches
  // a broken pipeline, not the accuracy figure).
  const double dx = end.pose.pose.position.x - first.pose.pose.position.x;
  const double dy = end.pose.pose.position.y - first.pose.pose.position.y;
  EXPECT_LT(std::hypot(dx, dy), 0.3);
  EXPECT_LT(std::abs(end.pose.pose.position.z - first.pose.pose.position.z), 0.3);
  EXPECT_GT(std::stoi(c.diag["frames with a barometer residual"]), 350);
  // Moved in between: about 23 m of path in a 4 x 5 m area.
  double path = 0.0;
  for (std::size_t i = 1; i < c.odom.size(); ++i)
    path += std::hypot(c.odom[i].pose.pose.position.x - c.odom[i - 1].pose.pose.position.x,
                       c.odom[i].pose.pose.position.y - c.odom[i - 1].pose.pose.position.y);
  EXPECT_GT(path, 15.0);
  EXPECT_LT(path, 35.0);
  // TF odom -> base_link at the last odometry stamp equals the odometry pose.
  geometry_msgs::TransformStamped t;
  ASSERT_NO_THROW(t = tf.lookupTransform("odom", "base_link", end.header.stamp));
  EXPECT_NEAR(t.transform.translation.x, end.pose.pose.position.x, 1e-6);
  EXPECT_NEAR(t.transform.translation.y, end.pose.pose.position.y, 1e-6);
  EXPECT_NEAR(std::abs(t.transform.rotation.w), std::abs(end.pose.pose.orientation.w), 1e-6);
  // publish_extrinsics_tf: the config's radar pose as a static TF base_link -> radar.
  ASSERT_NO_THROW(t = tf.lookupTransform("base_link", "radar", ros::Time(0)));
  EXPECT_NEAR(t.transform.translation.x, 0.03, 1e-9);
  EXPECT_NEAR(t.transform.translation.z, -0.06, 1e-9);
  EXPECT_NEAR(std::abs(t.transform.rotation.x), 0.918681231167, 1e-6);
  EXPECT_NEAR(std::abs(t.transform.rotation.w), 0.033880048164, 1e-6);
  EXPECT_GT(c.diag_updates, 0);
  EXPECT_EQ(c.diag["callback errors"], "0");
  // The radar-IMU time offset estimated (rio_offline: 0.0080 s from the prior 0.00925 s).
  EXPECT_EQ(c.diag["radar time offset"], "estimated (prior: radar_time_offset)");
  EXPECT_NEAR(std::stod(c.diag["radar time offset [s]"]), 0.0076, 0.002);
  EXPECT_EQ(c.diag["frames with the time offset at its bound"], "0");
}

// The bag played twice in a row (`rosbag play -l`; the soak scripts/bench/soak_rio.sh found this):
// the second loop repeats the trigger and scan sequence numbers 40 s earlier. The estimator
// restarts on the time jump, the trigger matching on the sequence restart, the path with
// them: the second loop is tracked like the first (before the fix: 14 odometry messages of
// 402, every other scan "without trigger").
TEST(RioNodelet, TiBagPlayedInALoopTracksEveryLoop) {
  CORAL_REQUIRE_DATA("ti_mmwave_demo");
  ros::NodeHandle nh;
  Collector c;
  ros::Subscriber so = odometryOf(nh, "/loop/odometry", &c);
  ros::Subscriber sd = diagnosticsOf(nh, "rio_loop", &c);
  nav_msgs::Path path;
  ros::Subscriber sp =
      nh.subscribe<nav_msgs::Path>("/loop/path", 10, [&c, &path](const nav_msgs::PathConstPtr& m) {
        std::lock_guard<std::mutex> l(c.m);
        path = *m;
      });
  ros::AsyncSpinner spinner(2);
  spinner.start();
  playTiBag(nh, coral_data + "/ti_mmwave_rospkg_demo.bag", "/loop", 2);
  ros::WallDuration(1.0).sleep();  // a diagnostics update after the last input
  std::lock_guard<std::mutex> l(c.m);
  std::size_t second = 0;  // index of the first odometry message of the second loop
  for (std::size_t i = 1; i < c.odom.size() && second == 0; ++i)
    if (c.odom[i].header.stamp.toSec() < c.odom[i - 1].header.stamp.toSec() - 1.0) second = i;
  ASSERT_GT(second, 0u) << "no second loop in " << c.odom.size() << " odometry messages; "
                        << c.summary;
  EXPECT_GE(second, 350u);
  EXPECT_GE(c.odom.size() - second, 350u)
      << "second loop; scans without trigger " << c.diag["scans without trigger"];
  EXPECT_LE(c.odom.size() - second, second + 2) << "no more frames than in the first loop";
  EXPECT_EQ(c.diag["trigger sequence restarts"], "1");
  EXPECT_EQ(c.diag["scans without trigger"], "0");
  EXPECT_GE(std::stol(c.diag["time jumps back"]), 1);
  EXPECT_EQ(c.diag["callback errors"], "0");
  // The path restarted with the odometry: only the second loop's poses.
  ASSERT_FALSE(path.poses.empty());
  EXPECT_LE(path.poses.size(), c.odom.size() - second);
  EXPECT_GE(path.poses.front().header.stamp.toSec(), c.odom[second].header.stamp.toSec());
}

namespace {

sensor_msgs::Imu imuAt(double t, double gyro_z) {
  sensor_msgs::Imu m;
  m.header.stamp = ros::Time(t);
  m.header.frame_id = "bad_base";
  m.linear_acceleration.z = 9.81;
  m.angular_velocity.z = gyro_z;
  return m;
}

// Static reflectors in front of a standing radar (zero Doppler); with_velocity false drops the
// radial-velocity field.
sensor_msgs::PointCloud2 scanAt(double t, int n, bool with_velocity, const std::string& frame) {
  sensor_msgs::PointCloud2 c;
  c.header.stamp = ros::Time(t);
  c.header.frame_id = frame;
  sensor_msgs::PointCloud2Modifier mod(c);
  if (with_velocity)
    mod.setPointCloud2Fields(
        4, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32, "z",
        1, sensor_msgs::PointField::FLOAT32, "velocity", 1, sensor_msgs::PointField::FLOAT32);
  else
    mod.setPointCloud2FieldsByString(1, "xyz");
  mod.resize(n);
  sensor_msgs::PointCloud2Iterator<float> x(c, "x"), y(c, "y"), z(c, "z");
  for (int i = 0; i < n; ++i, ++x, ++y, ++z) {
    *x = 2.0f + 0.3f * static_cast<float>(i % 7);
    *y = -1.5f + 0.5f * static_cast<float>(i % 6);
    *z = -0.4f + 0.2f * static_cast<float>(i % 4);
  }
  if (with_velocity) {
    sensor_msgs::PointCloud2Iterator<float> v(c, "velocity");
    for (int i = 0; i < n; ++i, ++v) *v = 0.0f;
  }
  return c;
}

// Standing data over [t0, t1): IMU at 200 Hz (rate gyro_z about z), a radar scan of `points`
// reflectors at 10 Hz (2 ms before its IMU sample), paced at 10x real time.
void playStanding(const ros::Publisher& imu, const ros::Publisher& radar, double t0, double t1,
                  bool with_velocity, int points, const std::string& radar_frame,
                  double gyro_z = 0.0, double imu_shift = 0.0) {
  for (double t = t0; t < t1; t += 0.005) {
    imu.publish(imuAt(t + imu_shift, gyro_z));
    if (std::lround((t - t0) / 0.005) % 20 == 19)
      radar.publish(scanAt(t - 0.002, points, with_velocity, radar_frame));
    ros::WallDuration(0.0005).sleep();
  }
}

// The nodelet of namespace `ns` under test: its odometry and the diagnostics of task `name`
// collected, publishers of its imu and radar inputs (connected), a running spinner.
struct Harness {
  Harness(const std::string& ns, const std::string& name)
      : so(odometryOf(nh, ns + "/odometry", &c)),
        sd(diagnosticsOf(nh, name, &c)),
        pi(nh.advertise<sensor_msgs::Imu>(ns + "/imu", 5000)),
        pr(nh.advertise<sensor_msgs::PointCloud2>(ns + "/radar", 100)),
        spinner(2) {
    spinner.start();
    waitFor(nh, pi);
    waitFor(nh, pr);
  }
  ros::NodeHandle nh;
  Collector c;
  ros::Subscriber so, sd;
  ros::Publisher pi, pr;
  ros::AsyncSpinner spinner;
};

}  // namespace

TEST(RioNodelet, BadInputsGiveDiagnosticsAndRecovery) {
  Harness h("/bad", "rio_bad");
  Collector& c = h.c;
  auto play = [&](double t0, double t1, bool with_velocity, int points) {
    playStanding(h.pi, h.pr, t0, t1, with_velocity, points, "radar");
  };
  play(1000.0, 1003.0, true, 30);  // static start: initialises and tracks
  ros::WallDuration(0.5).sleep();
  const std::size_t tracked_before = [&] {
    std::lock_guard<std::mutex> l(c.m);
    return c.odom.size();
  }();
  EXPECT_GT(tracked_before, 5u) << "a standing start should initialise within 3 s";
  play(1003.0, 1004.0, false, 30);  // no radial-velocity field
  play(1004.0, 1005.0, true, 0);    // empty scans
  play(1005.5, 1007.0, true, 30);   // 0.5 s IMU gap
  play(990.0, 994.0, true, 30);     // time jumps back 17 s: reset, re-initialise
  ros::WallDuration(2.5).sleep();   // a diagnostics update (1 s period) after the last input
  EXPECT_GT(diagValue(c, "scans without radial velocity"), 0);
  EXPECT_GT(diagValue(c, "empty scans"), 0);
  EXPECT_GT(diagValue(c, "imu gaps"), 0);
  EXPECT_GT(diagValue(c, "time jumps back"), 0);
  EXPECT_EQ(diagValue(c, "callback errors"), 0);
  std::lock_guard<std::mutex> l(c.m);
  // Recovery: after the jump back the odometry starts again from the new standing data.
  ASSERT_FALSE(c.odom.empty());
  EXPECT_LT(c.odom.back().header.stamp.toSec(), 995.0);
  EXPECT_GT(c.odom.back().header.stamp.toSec(), 991.0);
  for (const nav_msgs::Odometry& o : c.odom)
    EXPECT_LT(std::hypot(o.pose.pose.position.x, o.pose.pose.position.y), 0.2)
        << "a standing radar must not drift";
}

// extrinsics_source tf: no odometry and a diagnostic naming the missing transform until TF has
// it; then the odometry starts with exactly that transform (the landmarks land where the TF
// rotation puts the reflectors, not where the config file's TI extrinsics would).
TEST(RioNodelet, ExtrinsicsFromTfWaitForTheTransformThenUseIt) {
  Harness h("/late_tf", "rio_late_tf");
  Collector& c = h.c;
  std::vector<sensor_msgs::PointCloud2> landmarks;
  ros::Subscriber sl = h.nh.subscribe<sensor_msgs::PointCloud2>(
      "/late_tf/landmarks", 100, [&c, &landmarks](const sensor_msgs::PointCloud2ConstPtr& m) {
        std::lock_guard<std::mutex> l(c.m);
        landmarks.push_back(*m);
      });
  auto play = [&](double t0, double t1) {
    playStanding(h.pi, h.pr, t0, t1, true, 30, "late_radar");
  };
  play(2000.0, 2002.0);  // standing, no TF yet
  ros::WallDuration(2.5).sleep();
  {
    std::lock_guard<std::mutex> l(c.m);
    EXPECT_TRUE(c.odom.empty()) << "no odometry without the extrinsics";
    EXPECT_NE(c.summary.find("waiting for TF late_base <- late_radar"), std::string::npos)
        << c.summary;
    EXPECT_EQ(c.level, diagnostic_msgs::DiagnosticStatus::WARN);
  }
  EXPECT_GT(diagValue(c, "radar frames waiting for extrinsics"), 5);
  // The radar 0.1, 0.2, 0.3 m from the IMU, turned +90 deg about z.
  tf2_ros::StaticTransformBroadcaster broadcaster;
  geometry_msgs::TransformStamped t;
  t.header.stamp = ros::Time(2000.0);
  t.header.frame_id = "late_base";
  t.child_frame_id = "late_radar";
  t.transform.translation.x = 0.1;
  t.transform.translation.y = 0.2;
  t.transform.translation.z = 0.3;
  t.transform.rotation.z = std::sqrt(0.5);
  t.transform.rotation.w = std::sqrt(0.5);
  broadcaster.sendTransform(t);
  ros::WallDuration(0.5).sleep();
  play(2002.0, 2005.0);
  ros::WallDuration(2.5).sleep();
  std::lock_guard<std::mutex> l(c.m);
  EXPECT_GT(c.odom.size(), 5u) << c.summary;
  EXPECT_EQ(c.diag["extrinsics from"], "TF late_base <- late_radar");
  EXPECT_EQ(c.diag["extrinsics translation [m]"], "0.1 0.2 0.3");
  ASSERT_FALSE(landmarks.empty());
  const sensor_msgs::PointCloud2& cloud = landmarks.back();
  ASSERT_GT(cloud.width * cloud.height, 0u);
  // Reflectors at x_r 2..3.8 m, y_r -1.5..1 m in the radar frame; the standing body is level
  // with zero yaw, so in the odometry frame x = -y_r + 0.1 (-0.9..1.6), y = x_r + 0.2
  // (2.2..4). The config file's extrinsics (TI, about 45 deg right) would give y < 0.
  sensor_msgs::PointCloud2ConstIterator<float> x(cloud, "x"), y(cloud, "y");
  for (; x != x.end(); ++x, ++y) {
    EXPECT_GT(*y, 2.0);
    EXPECT_LT(*y, 4.2);
    EXPECT_GT(*x, -1.1);
    EXPECT_LT(*x, 1.8);
  }
}

// Refused input (rio_input.hpp, rio/imu_check.hpp): ERROR diagnostics with the reason, no
// odometry. First scans without the radial-velocity field, then a standing IMU whose rate is
// the TI gyro's bias read in deg/s (0.44 "rad/s").
TEST(RioNodelet, RefusedInputGivesErrorDiagnosticsAndNoOdometry) {
  Harness h("/refuse", "rio_refuse");
  Collector& c = h.c;
  auto summary = [&c] {
    std::lock_guard<std::mutex> l(c.m);
    return std::make_pair(c.level, c.summary);
  };
  playStanding(h.pi, h.pr, 3000.0, 3001.0, false, 30, "radar");
  ros::WallDuration(2.5).sleep();  // a diagnostics update (1 s period) after the last scan
  std::pair<int, std::string> d = summary();
  EXPECT_EQ(d.first, diagnostic_msgs::DiagnosticStatus::ERROR) << d.second;
  EXPECT_NE(d.second.find("input refused: radar cloud has no radial-velocity field 'velocity' "
                          "(fields: x, y, z; set ros/velocity_field)"),
            std::string::npos)
      << d.second;
  EXPECT_GT(diagValue(c, "scans without radial velocity"), 5);
  playStanding(h.pi, h.pr, 3001.0, 3004.0, true, 30, "radar", 0.44);
  ros::WallDuration(2.5).sleep();
  d = summary();
  EXPECT_EQ(d.first, diagnostic_msgs::DiagnosticStatus::ERROR) << d.second;
  EXPECT_NE(d.second.find("input refused, no odometry: IMU units: at rest"), std::string::npos)
      << d.second;
  EXPECT_NE(d.second.find("(in deg/s?)"), std::string::npos) << d.second;
  std::lock_guard<std::mutex> l(c.m);
  EXPECT_TRUE(c.odom.empty()) << c.odom.size() << " odometry messages from refused input";
  EXPECT_EQ(c.diag["callback errors"], "0");
}

namespace {

std::vector<std::string> loadedNodelets() {
  nodelet::NodeletList srv;
  if (!ros::service::call("/rio_test_manager/list", srv)) return {"<list failed>"};
  return srv.response.nodelets;
}

// Loads RioNodelet as `name` with its config file holding `yaml` (none when yaml is null) and
// one extra private parameter; true when the manager loaded it.
bool loadWithConfig(const std::string& name, const char* yaml, const std::string& param = "",
                    double value = 0.0) {
  if (yaml) {
    std::string tag = name;
    std::replace(tag.begin(), tag.end(), '/', '_');
    const std::string path = coral_test::tempPath("rio_load" + tag, ".yaml");
    std::ofstream(path) << yaml;
    ros::param::set(name + "/config_file", path);
  }
  if (!param.empty()) ros::param::set(name + "/" + param, value);
  nodelet::NodeletLoad srv;
  srv.request.name = name;
  srv.request.type = "coral_introspection/RioNodelet";
  return ros::service::call("/rio_test_manager/load_nodelet", srv) && srv.response.success;
}

}  // namespace

// As CoralNodelet: a configuration error fails the load (onInit throws; the manager answers
// false and does not list the nodelet), instead of a loaded nodelet doing nothing.
TEST(RioNodelet, ConfigErrorsFailTheLoad) {
  ASSERT_TRUE(ros::service::waitForService("/rio_test_manager/load_nodelet", ros::Duration(20.0)));
  const char* good = "extrinsics: {translation: [0, 0, 0], rotation: [0, 0, 0, 1]}\n";
  EXPECT_FALSE(loadWithConfig("/l_noext/rio", "solver: {window_size: 6}\n"));
  EXPECT_FALSE(loadWithConfig("/l_misspelt/rio", "extrinsic: {translation: [0, 0, 0]}\n"));
  EXPECT_FALSE(loadWithConfig("/l_unknown/rio",
                              "extrinsics: {translation: [0, 0, 0], rotation: [0, 0, 0, 1]}\n"
                              "window_size: 8\n"));
  EXPECT_FALSE(loadWithConfig("/l_empty/rio", ""));
  EXPECT_FALSE(loadWithConfig("/l_none/rio", nullptr));  // no config_file at all
  EXPECT_FALSE(loadWithConfig("/l_heap/rio", good, "heap_release_interval", -1.0));
  // Issue 23: a group given twice, and a misspelt private parameter (unknown key
  // heap_release_intervall (did you mean heap_release_interval?)), were silently ignored.
  EXPECT_FALSE(loadWithConfig("/l_twice/rio", (std::string(good) + good).c_str()));
  EXPECT_FALSE(loadWithConfig("/l_param/rio", good, "heap_release_intervall", 1.0));
  const std::vector<std::string> names = loadedNodelets();
  EXPECT_EQ(std::count_if(names.begin(), names.end(),
                          [](const std::string& n) { return n.rfind("/l_", 0) == 0; }),
            0);
  // The same manager still loads (and unloads) a valid one.
  EXPECT_TRUE(loadWithConfig("/l_good/rio", good, "heap_release_interval", 1.0));
  nodelet::NodeletUnload un;
  un.request.name = "/l_good/rio";
  EXPECT_TRUE(ros::service::call("/rio_test_manager/unload_nodelet", un) && un.response.success);
}

// barometer/enabled: the nodelet subscribes `baro` (sensor_msgs/FluidPressure) and the
// estimator puts a barometer residual on the frames that have samples (diagnostics count
// both). The samples of a 3 s standing sequence are sent first; the estimator keeps the
// newest 2 s of them until the frames that use them arrive.
namespace {

// Loads RioNodelet as `ns`/rio with identity extrinsics and one more config line; true when
// the manager loaded it.
bool loadIdentityRig(const std::string& ns, const std::string& line) {
  const std::string yaml = "extrinsics: {translation: [0, 0, 0], rotation: [0, 0, 0, 1]}\n" + line;
  return ros::service::waitForService("/rio_test_manager/load_nodelet", ros::Duration(20.0)) &&
         loadWithConfig(ns + "/rio", yaml.c_str());
}

}  // namespace

TEST(RioNodelet, BarometerIsSubscribedAndUsed) {
  ASSERT_TRUE(loadIdentityRig("/baro", "barometer: {enabled: true}\n"));
  Harness h("/baro", "/baro/rio");
  ros::Publisher pb = h.nh.advertise<sensor_msgs::FluidPressure>("/baro/baro", 500);
  waitFor(h.nh, pb);
  for (int k = 0; k < 150; ++k) {  // 50 Hz over [4000, 4003) s
    sensor_msgs::FluidPressure m;
    m.header.stamp = ros::Time(4000.0 + 0.02 * k);
    m.fluid_pressure = 100184.0;
    pb.publish(m);
  }
  ros::WallDuration(0.5).sleep();
  playStanding(h.pi, h.pr, 4000.0, 4003.0, true, 30, "radar");
  ros::WallDuration(2.5).sleep();
  EXPECT_EQ(diagValue(h.c, "barometer messages"), 150);
  EXPECT_GT(diagValue(h.c, "frames with a barometer residual"), 10);
  EXPECT_EQ(diagValue(h.c, "bad barometer messages"), 0);
  std::lock_guard<std::mutex> l(h.c.m);
  ASSERT_FALSE(h.c.odom.empty());
  EXPECT_NEAR(h.c.odom.back().pose.pose.position.z, 0.0, 0.05);  // standing: no height change
}

// IMU stamps 0.5 s ahead of the radar's with time_offset/estimate: no offset within the bound
// (0.1 s) and no radar latency up to time_offset/max_latency (0.3 s) explains the arrival lag,
// so the input is refused (ERROR diagnostics) after 20 frames; no odometry after that.
TEST(RioNodelet, ImuClockFarAheadIsRefusedInDiagnostics) {
  ASSERT_TRUE(loadIdentityRig("/clock", "time_offset: {estimate: true}\n"));
  Harness h("/clock", "/clock/rio");
  playStanding(h.pi, h.pr, 5000.0, 5004.0, true, 30, "radar", 0.0, 0.5);
  ros::WallDuration(2.5).sleep();
  std::lock_guard<std::mutex> l(h.c.m);
  EXPECT_EQ(h.c.level, diagnostic_msgs::DiagnosticStatus::ERROR) << h.c.summary;
  EXPECT_NE(h.c.summary.find("input refused, no odometry: radar-IMU time offset: when a radar "
                             "frame arrives, the newest IMU stamp minus the frame time is 0.5"),
            std::string::npos)
      << h.c.summary;
  EXPECT_NE(h.c.summary.find("(IMU stamps late?)"), std::string::npos) << h.c.summary;
  // 40 frames; the first 20 are judged together (2 s), the odometry starts after 1 s of rest.
  EXPECT_LE(h.c.odom.size(), 15u);
  EXPECT_GE(std::stol(h.c.diag["rejected frames"]), 15);
  EXPECT_EQ(h.c.diag["callback errors"], "0");
}

// main(): test/rostest/rostest_main.cpp.
const coral_test::RostestNode coral_test::kRostestNode{"rio_nodelet_test", 0};
