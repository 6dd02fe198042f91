// ROS inputs of the radar-inertial odometry: radial-velocity field, missing field, zero
// stamps, trigger pairing by sequence number (the TI recording's timing).
#include <gtest/gtest.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <cmath>
#include <filesystem>

#include "coral_introspection/config/yaml_tree.hpp"
#include "coral_introspection/rio/config_yaml.hpp"
#include "coral_introspection/ros/rio_input.hpp"
#include "support/source_dir.hpp"

namespace ra = coral_introspection::ros_adapters;
namespace rio = coral_introspection::rio;

namespace {

sensor_msgs::PointCloud2 cloud(uint32_t seq, double stamp, bool with_velocity) {
  rio::RadarFrame f;
  f.points = {rio::Vec3(1, 2, 3), rio::Vec3(4, -5, 0.5)};
  f.radial_velocity = {0.25, -1.5};
  std_msgs::Header h;
  h.seq = seq;
  h.stamp = ros::Time(stamp);
  h.frame_id = "radar";
  sensor_msgs::PointCloud2 c = ra::radarFrameToCloud(f, h, "velocity");
  c.header.seq = seq;
  if (!with_velocity) c.fields.pop_back();
  return c;
}

// Scans timed by a trigger topic (the TI bag's layout).
ra::RioInputConfig triggerTimed() {
  ra::RioInputConfig cfg;
  cfg.time_source = "trigger";
  cfg.trigger_topic = "trigger";
  return cfg;
}

// The trigger message with this sequence number and stamp, given to `in`.
std::vector<rio::RadarFrame> sendTrigger(ra::RioInput* in, uint32_t seq, double stamp) {
  std_msgs::Header h;
  h.seq = seq;
  h.stamp = ros::Time(stamp);
  return in->trigger(h);
}

}  // namespace

TEST(RioInput, ReadsPointsAndRadialVelocityWithHeaderTime) {
  ra::RioInput in{ra::RioInputConfig()};
  std::string err;
  const std::vector<rio::RadarFrame> f = in.radar(cloud(3, 12.5, true), &err);
  ASSERT_EQ(f.size(), 1u) << err;
  EXPECT_TRUE(err.empty());
  EXPECT_DOUBLE_EQ(f[0].t, 12.5);
  ASSERT_EQ(f[0].points.size(), 2u);
  EXPECT_NEAR(f[0].points[1].y(), -5.0, 1e-6);
  ASSERT_EQ(f[0].radial_velocity.size(), 2u);
  EXPECT_NEAR(f[0].radial_velocity[1], -1.5, 1e-6);
}

TEST(RioInput, MissingVelocityFieldAndZeroStampAreReported) {
  ra::RioInput in{ra::RioInputConfig()};
  std::string err;
  std::vector<rio::RadarFrame> f = in.radar(cloud(1, 5.0, false), &err);
  EXPECT_TRUE(f.empty());  // refused: the odometry would be the IMU's dead reckoning
  EXPECT_NE(err.find("no radial-velocity field 'velocity' (fields: x, y, z; set "
                     "ros/velocity_field)"),
            std::string::npos)
      << err;
  EXPECT_EQ(in.counters().no_velocity_field, 1);
  f = in.radar(cloud(2, 0.0, true), &err);  // header time, zero stamp
  EXPECT_TRUE(f.empty());
  EXPECT_EQ(in.counters().bad_clouds, 1);
}

TEST(RioInput, TriggerOfTheSameSequenceNumberGivesTheTime) {
  ra::RioInputConfig cfg;
  cfg.time_source = "trigger";
  cfg.trigger_topic = "trigger";
  ASSERT_EQ(cfg.validate(), "");
  ra::RioInput in(cfg);
  std::string err;
  std_msgs::Header t109, t110;
  t109.seq = 109;
  t109.stamp = ros::Time(100.0);
  t110.seq = 110;
  t110.stamp = ros::Time(100.1);
  EXPECT_TRUE(in.trigger(t109).empty());
  EXPECT_TRUE(in.trigger(t110).empty());
  // The TI scans carry zero stamps; scan 109 arrives after trigger 110 and must take the
  // time of trigger 109 (same seq), not of the latest trigger.
  std::vector<rio::RadarFrame> f = in.radar(cloud(109, 0.0, true), &err);
  ASSERT_EQ(f.size(), 1u);
  EXPECT_DOUBLE_EQ(f[0].t, 100.0);
  // A scan that arrives before its trigger waits for it.
  EXPECT_TRUE(in.radar(cloud(111, 0.0, true), &err).empty());
  EXPECT_EQ(in.waitingScans(), 1);
  std_msgs::Header t111;
  t111.seq = 111;
  t111.stamp = ros::Time(100.2);
  f = in.trigger(t111);
  ASSERT_EQ(f.size(), 1u);
  EXPECT_DOUBLE_EQ(f[0].t, 100.2);
}

// A bag played in a loop (rosbag play -l) repeats the trigger and scan sequence numbers
// 40 s earlier. The old sequence's triggers have higher numbers than every new one; kept, they
// would evict each new trigger on arrival (capacity 64, lowest seq first) and the new scans
// would never be stamped (the soak of RioNodelet: no odometry after the first loop).
TEST(RioInput, TriggerSequenceRestartedByALoopingBagStampsTheNewScans) {
  ra::RioInput in(triggerTimed());
  std::string err;
  auto trigger = [&in](uint32_t seq, double stamp) { return sendTrigger(&in, seq, stamp); };
  auto loop = [&](double t0) {  // 412 frames: trigger first, then its scan (the TI timing)
    long stamped = 0;
    for (uint32_t seq = 109; seq < 521; ++seq) {
      const double t = t0 + 0.1 * (seq - 109);
      EXPECT_TRUE(trigger(seq, t).empty());
      const std::vector<rio::RadarFrame> f = in.radar(cloud(seq, 0.0, true), &err);
      if (f.size() == 1u && f[0].t == t) ++stamped;
    }
    EXPECT_TRUE(trigger(521, t0 + 41.2).empty());  // the last trigger has no scan
    return stamped;
  };
  EXPECT_EQ(loop(1000.0), 412);
  EXPECT_EQ(in.triggerRestarts(), 0);
  EXPECT_EQ(loop(1000.0), 412) << "second loop: every scan stamped with its new trigger";
  EXPECT_EQ(loop(1000.0), 412);
  EXPECT_EQ(in.triggerRestarts(), 2);
  EXPECT_EQ(in.counters().unmatched_scans, 0);
  EXPECT_EQ(in.waitingScans(), 0);
}

// The same restart when the new sequence's first scans arrive before its first trigger: they
// wait for the new triggers, not take the stamps of the old sequence's (same numbers); old
// scans still waiting at the restart are dropped and counted.
TEST(RioInput, ScansOfANewSequenceBeforeItsTriggersWaitForThem) {
  ra::RioInput in(triggerTimed());
  std::string err;
  auto trigger = [&in](uint32_t seq, double stamp) { return sendTrigger(&in, seq, stamp); };
  for (uint32_t seq = 10; seq < 20; ++seq) {
    trigger(seq, 100.0 + seq);
    ASSERT_EQ(in.radar(cloud(seq, 0.0, true), &err).size(), 1u);
  }
  EXPECT_TRUE(in.radar(cloud(20, 0.0, true), &err).empty());  // waits for trigger 20
  // Restart: scans 10, 11 first (trigger 10 and 11 of the old sequence are still stored).
  EXPECT_TRUE(in.radar(cloud(10, 0.0, true), &err).empty());
  EXPECT_EQ(in.counters().unmatched_scans, 1);  // old scan 20 dropped
  EXPECT_TRUE(in.radar(cloud(11, 0.0, true), &err).empty());
  EXPECT_EQ(in.waitingScans(), 2);
  std::vector<rio::RadarFrame> f = trigger(10, 50.0);  // the new sequence's triggers
  ASSERT_EQ(f.size(), 1u);
  EXPECT_DOUBLE_EQ(f[0].t, 50.0);
  f = trigger(11, 50.1);
  ASSERT_EQ(f.size(), 1u);
  EXPECT_DOUBLE_EQ(f[0].t, 50.1);
  EXPECT_EQ(in.triggerRestarts(), 1);
  EXPECT_EQ(in.waitingScans(), 0);
  // Then trigger first again.
  trigger(12, 50.2);
  f = in.radar(cloud(12, 0.0, true), &err);
  ASSERT_EQ(f.size(), 1u);
  EXPECT_DOUBLE_EQ(f[0].t, 50.2);
  EXPECT_EQ(in.counters().unmatched_scans, 1);
}

namespace {

// The ros group of a rio config file given as YAML text.
bool loadInput(const std::string& yaml, ra::RioInputConfig* cfg, std::string* err) {
  coral_introspection::config::ParamTree tree;
  return coral_introspection::config::parseYaml(yaml, &tree, err) &&
         ra::loadRioInputConfig(tree, cfg, err);
}

}  // namespace

TEST(RioInput, ConfigFromYamlIsValidated) {
  ra::RioInputConfig cfg;
  std::string err;
  EXPECT_TRUE(loadInput("ros: {time_source: trigger, trigger_topic: /t}", &cfg, &err)) << err;
  EXPECT_EQ(cfg.trigger_topic, "/t");
  EXPECT_FALSE(loadInput("ros: {time_source: gps}", &cfg, &err));
  EXPECT_NE(err.find("time_source"), std::string::npos);
  cfg = ra::RioInputConfig();
  EXPECT_FALSE(loadInput("ros: {time_source: trigger}", &cfg, &err));
  // A misspelt key would leave the topic at its default: refused with the nearest key.
  cfg = ra::RioInputConfig();
  EXPECT_FALSE(loadInput("ros: {imu_topc: /imu}", &cfg, &err));
  EXPECT_EQ(err, "unknown key ros/imu_topc (did you mean imu_topic?)");
  EXPECT_FALSE(loadInput("ros: [a, b]", &cfg, &err));
  EXPECT_EQ(err, "group ros must be a map of parameters");
  EXPECT_FALSE(loadInput("ros: {trigger_seq_offset: one}", &cfg, &err));
  EXPECT_EQ(err, "parameter ros/trigger_seq_offset must be an integer (got 'one')");
}

// Every RioNodelet / rio_offline config in config/ loads without errors.
TEST(RioInput, EveryRioConfigLoads) {
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(coral_test::sourceDir() + "/config")) {
    const std::string name = e.path().filename().string();
    if (name.rfind("rio_", 0) != 0) continue;
    SCOPED_TRACE(name);
    ++n;
    coral_introspection::config::ParamTree tree;
    rio::RioConfig cfg;
    ra::RioInputConfig in;
    std::string err;
    ASSERT_TRUE(coral_introspection::config::loadYamlFile(e.path().string(), &tree, &err)) << err;
    EXPECT_TRUE(rio::loadRioConfig(tree, &cfg, &err, {{"ros"}})) << err;
    EXPECT_TRUE(ra::loadRioInputConfig(tree, &in, &err)) << err;
  }
  EXPECT_GE(n, 3);
}

TEST(RioInput, ExtrinsicsFromTfTransformMapRadarPointsIntoTheBody) {
  // body <- radar: radar 0.1, 0.2, 0.3 m from the IMU, turned +90 deg about z.
  geometry_msgs::Transform t;
  t.translation.x = 0.1;
  t.translation.y = 0.2;
  t.translation.z = 0.3;
  t.rotation.z = std::sqrt(0.5);
  t.rotation.w = std::sqrt(0.5);
  rio::Extrinsics e;
  std::string err;
  ASSERT_TRUE(ra::extrinsicsFromTransform(t, &e, &err)) << err;
  // A reflector 2 m ahead of the radar is 2 m to the body's left, offset by the lever arm.
  const rio::Vec3 p = e.R * rio::Vec3(2, 0, 0) + e.t;
  EXPECT_NEAR(p.x(), 0.1, 1e-12);
  EXPECT_NEAR(p.y(), 2.2, 1e-12);
  EXPECT_NEAR(p.z(), 0.3, 1e-12);
  t.rotation.w = 0.9;  // not a unit quaternion: refused, *e unchanged
  EXPECT_FALSE(ra::extrinsicsFromTransform(t, &e, &err));
  EXPECT_NE(err.find("rigid transform"), std::string::npos) << err;
  EXPECT_NEAR(e.t.y(), 0.2, 1e-12);
}
