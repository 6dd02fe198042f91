// rio_offline end to end: the TI bag gives its trajectory; every bad input of the "refuse,
// don't guess" issue ends with exit status 1, the reason on stderr, no trajectory file and no
// end-point figure. Bad bags are the shared TI bag rewritten by the test (rosbag C++ API).
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "support/run_tool.hpp"
#include "support/test_data.hpp"

using coral_test::tempPath;

namespace {

const std::string kTiConfig = coral_test::sourceDir() + "/config/rio_ti_mmwave.yaml";

bool exists(const std::string& path) { return std::ifstream(path).good(); }

struct Result {
  int status = -1;
  std::string out, err, trajectory;  // trajectory: the --output path
};

Result rioOffline(const std::string& bag, const std::string& config, const std::string& name,
                  const std::string& options = "") {
  Result r;
  r.trajectory = tempPath("rio_" + name, ".tum");
  std::remove(r.trajectory.c_str());
  const coral_test::ToolRun run =
      coral_test::runTool(RIO_OFFLINE_EXE, "--bag " + bag + " --config " + config + " --output " +
                                               r.trajectory + " " + options);
  r.status = run.status;
  r.out = run.out;
  r.err = run.err;
  return r;
}

// The figures of rio_offline's "loop end-point error" line; ok is false when it is absent.
struct LoopEnd {
  bool ok = false;
  double horizontal = 0.0, vertical = 0.0, yaw = 0.0, x = 0.0, y = 0.0;
};

LoopEnd loopEnd(const std::string& out) {
  LoopEnd e;
  const std::size_t at = out.find("loop end-point error: ");
  if (at == std::string::npos) return e;
  e.ok = std::sscanf(out.c_str() + at,
                     "loop end-point error: horizontal %lf m, vertical %lf m, yaw %lf deg; end "
                     "(x, y) in the start-heading frame (%lf, %lf) m",
                     &e.horizontal, &e.vertical, &e.yaw, &e.x, &e.y) == 5;
  return e;
}

// Refused: status 1, `reason` on stderr, no trajectory written, no end-point figure.
void expectRefused(const Result& r, const std::string& reason) {
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("refused: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(reason), std::string::npos) << r.err;
  EXPECT_FALSE(exists(r.trajectory)) << r.trajectory;
  EXPECT_EQ(r.out.find("loop end-point error"), std::string::npos) << r.out;
}

std::string writeConfig(const std::string& name, const std::string& text) {
  const std::string path = tempPath("rio_" + name, ".yaml");
  std::ofstream(path) << text;
  return path;
}

// The TI bag's first `seconds` (bag time) with one change.
enum class Edit {
  kNone,
  kRenameVelocityField,
  kGyroInDegrees,
  kAccInG,
  kImuClockPlus100s,
  kImuClockPlus0_5s,
  kImuClockMinus0_5s,
  kDropImu,
  kDropTrigger,
  kImuGapAt20s
};

std::string rewriteTiBag(const std::string& data, Edit edit, double seconds,
                         const std::string& name) {
  rosbag::Bag in(data + "/ti_mmwave_rospkg_demo.bag", rosbag::bagmode::Read);
  const std::string path = tempPath("rio_" + name, ".bag");
  rosbag::Bag out(path, rosbag::bagmode::Write);
  rosbag::View view(in);
  const ros::Time end = view.getBeginTime() + ros::Duration(seconds);
  double imu_t0 = -1.0;
  for (const rosbag::MessageInstance& m : view) {
    if (m.getTime() > end) break;
    const bool trigger = m.getTopic() == "/sensor_platform/radar_right/trigger";
    if (sensor_msgs::Imu::Ptr imu = m.instantiate<sensor_msgs::Imu>()) {
      const double t = imu->header.stamp.toSec();
      if (imu_t0 < 0.0) imu_t0 = t;
      if (edit == Edit::kDropImu ||
          (edit == Edit::kImuGapAt20s && t - imu_t0 >= 20.0 && t - imu_t0 < 22.0))
        continue;
      if (edit == Edit::kGyroInDegrees) {
        imu->angular_velocity.x *= 180.0 / M_PI;
        imu->angular_velocity.y *= 180.0 / M_PI;
        imu->angular_velocity.z *= 180.0 / M_PI;
      }
      if (edit == Edit::kAccInG) {
        imu->linear_acceleration.x /= 9.81;
        imu->linear_acceleration.y /= 9.81;
        imu->linear_acceleration.z /= 9.81;
      }
      if (edit == Edit::kImuClockPlus100s) imu->header.stamp += ros::Duration(100.0);
      if (edit == Edit::kImuClockPlus0_5s) imu->header.stamp += ros::Duration(0.5);
      if (edit == Edit::kImuClockMinus0_5s) imu->header.stamp -= ros::Duration(0.5);
      out.write(m.getTopic(), m.getTime(), *imu);
    } else if (sensor_msgs::PointCloud2::Ptr cloud = m.instantiate<sensor_msgs::PointCloud2>()) {
      if (edit == Edit::kRenameVelocityField)
        for (sensor_msgs::PointField& f : cloud->fields)
          if (f.name == "velocity") f.name = "doppler";
      out.write(m.getTopic(), m.getTime(), *cloud);  // header.seq kept: triggers pair by it
    } else if (!(trigger && edit == Edit::kDropTrigger)) {
      out.write(m.getTopic(), m.getTime(), m);
    }
  }
  return path;
}

// The TUM file's rows (t x y z qx qy qz qw).
std::vector<std::vector<double>> readTum(const std::string& path) {
  std::vector<std::vector<double>> rows;
  std::ifstream f(path);
  std::vector<double> r(8);
  while (f >> r[0] >> r[1] >> r[2] >> r[3] >> r[4] >> r[5] >> r[6] >> r[7]) rows.push_back(r);
  return rows;
}

}  // namespace

// The good path: the figures of doc/rio.md (end-point error 0.053 m horizontal, the radar-IMU
// time offset estimated at 0.0080 s from its prior 0.00925 s, not refused; the barometer on).
// Iteration-bounded solves (solver/max_solver_time 10 s; the preset's 0.05 s per frame is never
// reached in Release, ~3 ms a frame): under the sanitizers a frame takes ~50 ms, and with
// another test beside it the time budget cut solves short and moved the end to 0.0487 m (the
// fresh-clone CI simulation of f6cf6a2).
TEST(RioOffline, TiBagGivesItsTrajectory) {
  CORAL_REQUIRE_DATA("ti_mmwave_demo");
  const Result r = rioOffline(coral_data + "/ti_mmwave_rospkg_demo.bag", kTiConfig, "good",
                              "--set solver/max_solver_time=10");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(readTum(r.trajectory).size(), 412u);
  EXPECT_NE(r.out.find("loop end-point error: horizontal 0.05"), std::string::npos) << r.out;
  // 0.00799 s in the Release build, 0.00800 s in the sanitizer build (clang): a range.
  const std::string key = "radar-IMU time offset: estimated ";
  const std::size_t at = r.out.find(key);
  ASSERT_NE(at, std::string::npos) << r.out;
  const double offset = std::stod(r.out.substr(at + key.size()));
  EXPECT_GT(offset, 0.0075) << r.out;
  EXPECT_LT(offset, 0.0085) << r.out;
  EXPECT_NE(r.out.find("at the bound on 0 frames"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("barometer: frames with a residual 402"), std::string::npos) << r.out;
}

// Issue 22's targets with the shipped config: the end within 0.10 m of the independent end
// pose (+0.04, +0.05) m in the start-heading frame, yaw within 2.5 deg of -3.2 deg, height
// within 0.10 m of the start (doc/rio.md: end (+0.034, -0.040) m, yaw -3.36 deg, +0.073 m).
// In-sample: the loop is the data the elevation sigma and the barometer's weights were
// checked on.
TEST(RioOffline, TiBagEndsWithinTheIssueTargets) {
  CORAL_REQUIRE_DATA("ti_mmwave_demo");
  const Result r = rioOffline(coral_data + "/ti_mmwave_rospkg_demo.bag", kTiConfig, "targets");
  ASSERT_EQ(r.status, 0) << r.err;
  const LoopEnd e = loopEnd(r.out);
  ASSERT_TRUE(e.ok) << r.out;
  EXPECT_LT(std::hypot(e.x - 0.04, e.y - 0.05), 0.10) << r.out;
  EXPECT_LT(std::abs(e.yaw + 3.2), 2.5) << r.out;
  EXPECT_LT(std::abs(e.vertical), 0.10) << r.out;
}

// time_offset/estimate=false with the elevation sigma of the defaults and the barometer off
// is the odometry of before the estimate (the figures of doc/rio.md before it: 0.0576215 m,
// -1.34299 m, -3.12789 deg). Not digit for digit: a sanitizer build on another CPU printed
// 0.0576156 m, -1.34298 m, -3.12801 deg (CI, 2026-12-02), so 2e-4 m and 2e-3 deg. Estimating
// the offset under the same settings moves the figures by 2.7e-3 m, 5.8e-3 m and 0.056 deg.
// Iteration-bounded solves (solver/max_solver_time 10 s, not the 0.05 s per frame of the
// preset; a Release frame takes ~3 ms): under the sanitizers a frame takes ~35 ms, and with
// another test beside it (ctest -j2) some hit 0.05 s and the figures moved by 2.9e-4 m.
TEST(RioOffline, TimeOffsetNotEstimatedIsTheOdometryOfBefore) {
  CORAL_REQUIRE_DATA("ti_mmwave_demo");
  const Result r = rioOffline(coral_data + "/ti_mmwave_rospkg_demo.bag", kTiConfig, "td_off",
                              "--set time_offset/estimate=false --set barometer/enabled=false "
                              "--set uncertainty/sigma_elevation=0.0088 "
                              "--set solver/max_solver_time=10");
  ASSERT_EQ(r.status, 0) << r.err;
  const LoopEnd e = loopEnd(r.out);
  ASSERT_TRUE(e.ok) << r.out;
  EXPECT_NEAR(e.horizontal, 0.0576215, 2e-4) << r.out;
  EXPECT_NEAR(e.vertical, -1.34299, 2e-4) << r.out;
  EXPECT_NEAR(e.yaw, -3.12789, 2e-3) << r.out;
  EXPECT_NE(r.out.find("radar-IMU time offset: 0.00925 s (configured, not estimated)"),
            std::string::npos)
      << r.out;
}

// The TI config with the barometer on (barometer/sigma as set there or the default) and
// ros/baro_topic replaced when `baro_topic` is given.
std::string tiConfigWithBarometer(const std::string& name, const std::string& baro_topic = "") {
  YAML::Node root = YAML::LoadFile(kTiConfig);
  root["barometer"]["enabled"] = true;
  if (!baro_topic.empty()) root["ros"]["baro_topic"] = baro_topic;
  YAML::Emitter e;
  e << root;
  return writeConfig(name, e.c_str());
}

// The barometer (on in the shipped config) removes the loop's vertical drift (-1.39 m without
// it; doc/rio.md: the barometer's start and end heights agree to 0.04 m). In-sample: the TI
// loop is the data barometer/sigma was chosen on.
TEST(RioOffline, TiBagWithTheBarometerEndsAtItsStartHeight) {
  CORAL_REQUIRE_DATA("ti_mmwave_demo");
  const Result r =
      rioOffline(coral_data + "/ti_mmwave_rospkg_demo.bag", tiConfigWithBarometer("baro"), "baro");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("barometer: frames with a residual 40"), std::string::npos) << r.out;
  const std::size_t at = r.out.find(" m, vertical ");
  ASSERT_NE(at, std::string::npos) << r.out;
  EXPECT_LT(std::abs(std::stod(r.out.substr(at + 13))), 0.1) << r.out;
}

TEST(RioOffline, BarometerTopicMissingIsRefused) {
  CORAL_REQUIRE_DATA("ti_mmwave_demo");
  expectRefused(rioOffline(coral_data + "/ti_mmwave_rospkg_demo.bag",
                           tiConfigWithBarometer("nobaro", "/sensor_platform/pressure"), "nobaro"),
                "the bag has no topic '/sensor_platform/pressure' (ros/baro_topic) (did you mean "
                "/sensor_platform/baro?)");
}

// Config errors come before the bag is opened: no data needed.
TEST(RioOffline, ConfigErrorsAreRefusedNamingTheKey) {
  const std::string bag = tempPath("rio_not_read", ".bag");
  const std::string ext = "extrinsics: {translation: [0, 0, 0], rotation: [0, 0, 0, 1]}\n";
  expectRefused(rioOffline(bag, writeConfig("empty", ""), "empty"), "the config is empty");
  expectRefused(rioOffline(bag, writeConfig("noext", "solver: {window_size: 6}\n"), "noext"),
                "extrinsics/translation is required");
  expectRefused(
      rioOffline(bag, writeConfig("misspelt", "extrinsic: {translation: [0, 0, 0]}\n"), "misspelt"),
      "unknown group extrinsic (did you mean extrinsics?)");
  expectRefused(rioOffline(bag, writeConfig("top", ext + "window_size: 8\n"), "top"),
                "unknown key window_size (did you mean solver/window_size?)");
  expectRefused(rioOffline(bag, writeConfig("ros", ext + "ros: {imu_topik: /imu}\n"), "ros"),
                "unknown key ros/imu_topik (did you mean imu_topic?)");
}

TEST(RioOffline, EmptyBagIsRefused) {
  const std::string bag = tempPath("rio_empty", ".bag");
  rosbag::Bag(bag, rosbag::bagmode::Write).close();
  const std::string cfg =
      writeConfig("plain", "extrinsics: {translation: [0, 0, 0], rotation: [0, 0, 0, 1]}\n");
  expectRefused(rioOffline(bag, cfg, "empty_bag"), "the bag has no messages");
  std::remove(bag.c_str());
}

TEST(RioOffline, BadTiBagsAreRefusedWithTheReason) {
  CORAL_REQUIRE_DATA("ti_mmwave_demo");
  struct Case {
    const char* name;
    Edit edit;
    const char* reason;
  };
  // 6 s of the standing start: the IMU units are judged after 1 s of rest.
  const std::vector<Case> cases = {
      {"no_velocity", Edit::kRenameVelocityField,
       "no radial-velocity field 'velocity' (fields: x, y, z, intensity, doppler; set "
       "ros/velocity_field)"},
      {"deg_per_s", Edit::kGyroInDegrees, "not in rad/s (in deg/s?)"},
      {"acc_in_g", Edit::kAccInG, "not in m/s^2 (in g?)"},
      {"clock", Edit::kImuClockPlus100s, "the IMU and radar clocks do not overlap"},
      // The estimate's bound (0.1 s) and the radar's latency (0.3 s) cannot explain it.
      {"imu_late", Edit::kImuClockPlus0_5s,
       "radar-IMU time offset: when a radar frame arrives, the newest IMU stamp minus the frame "
       "time is 0.613 s (median of 20 frames), more than time_offset/max_latency 0.3 s of radar "
       "latency plus time_offset/max_abs 0.1 s: the IMU clock is ahead of the radar stamps (IMU "
       "stamps late?)"},
      {"imu_early", Edit::kImuClockMinus0_5s,
       "the newest IMU stamp minus the frame time is -0.387 s (median of 20 frames), before the "
       "IMU covers them: the IMU clock is behind the radar stamps by more than time_offset/max_abs "
       "0.1 s (IMU stamps early?)"},
      {"no_imu", Edit::kDropImu,
       "the bag has no topic '/sensor_platform/imu' (ros/imu_topic); its sensor_msgs/Imu "
       "topics: none"},
      {"no_trigger", Edit::kDropTrigger,
       "the bag has no topic '/sensor_platform/radar_right/trigger' (ros/trigger_topic)"}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string bag = rewriteTiBag(coral_data, c.edit, 6.0, c.name);
    expectRefused(rioOffline(bag, kTiConfig, c.name), c.reason);
    std::remove(bag.c_str());
  }
  // A wrong topic in the config names the bag's topic of that type.
  YAML::Node cfg = YAML::LoadFile(kTiConfig);
  cfg["ros"]["imu_topic"] = "/imu";
  const std::string wrong_topic = writeConfig("wrong_topic", YAML::Dump(cfg));
  expectRefused(rioOffline(coral_data + "/ti_mmwave_rospkg_demo.bag", wrong_topic, "wrong_topic"),
                "the bag has no topic '/imu' (ros/imu_topic); its sensor_msgs/Imu topics: "
                "/sensor_platform/imu");
}

// 2 s without IMU while the device moves (20-22 s): bridged with the Doppler velocity and
// counted, the poses over the gap follow the motion instead of standing still.
TEST(RioOffline, ImuGapWhileMovingIsBridgedAndCounted) {
  CORAL_REQUIRE_DATA("ti_mmwave_demo");
  const std::string bag = rewriteTiBag(coral_data, Edit::kImuGapAt20s, 1e3, "gap");
  const Result r = rioOffline(bag, kTiConfig, "gap");
  std::remove(bag.c_str());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("imu gaps 21 (bridged with Doppler 21)"), std::string::npos) << r.out;
  const std::vector<std::vector<double>> tum = readTum(r.trajectory);
  ASSERT_EQ(tum.size(), 412u);
  const double t0 = tum.front()[0];
  double path = 0.0;
  int frozen = 0;
  for (std::size_t k = 1; k < tum.size(); ++k) {
    if (tum[k][0] - t0 < 20.0 || tum[k][0] - t0 > 22.1) continue;
    const double step = std::hypot(tum[k][1] - tum[k - 1][1], tum[k][2] - tum[k - 1][2]);
    path += step;
    frozen += step < 1e-3;
  }
  EXPECT_EQ(frozen, 0);
  EXPECT_GT(path, 1.8);  // without the gap: 2.4 m over these 2.1 s
}
