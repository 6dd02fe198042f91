// rostest: CoralNodelet in a nodelet manager next to another nodelet (a second instance),
// loaded and unloaded through the manager's services (see nodelet_manager.test); loads with
// invalid or misspelt parameters fail.
#include "coral_rostest_utils.hpp"
#include "rostest_main.hpp"

#include <nodelet/NodeletList.h>
#include <nodelet/NodeletLoad.h>
#include <nodelet/NodeletUnload.h>
#include <rosgraph_msgs/Log.h>

#include <algorithm>
#include <mutex>

using namespace coral_test;
using coral_introspection::AlignmentQuality;

namespace {

// Loads CoralNodelet as /<ns>/coral: its topics and service live in /<ns>, its private
// parameters (loaded by the launch file) in /<ns>/coral.
bool load(const std::string& ns) {
  nodelet::NodeletLoad srv;
  srv.request.name = "/" + ns + "/coral";
  srv.request.type = "coral_introspection/CoralNodelet";
  return ros::service::call("/manager/load_nodelet", srv) && srv.response.success;
}

std::vector<std::string> loaded() {
  nodelet::NodeletList srv;
  if (!ros::service::call("/manager/list", srv)) return {"<list failed>"};
  return srv.response.nodelets;
}

bool topicHasPublisher(const std::string& topic) {
  ros::master::V_TopicInfo topics;
  ros::master::getTopics(topics);
  return std::any_of(topics.begin(), topics.end(),
                     [&](const ros::master::TopicInfo& t) { return t.name == topic; });
}

TEST(Manager, TwoInstancesRunAndUnloadCleanly) {
  ros::NodeHandle nh;
  ASSERT_TRUE(ros::service::waitForService("/manager/load_nodelet", ros::Duration(20.0)));
  tf2_ros::TransformBroadcaster br;  // early: its first message must not be lost
  ASSERT_TRUE(load("first"));
  ASSERT_TRUE(load("second"));
  auto names = loaded();
  EXPECT_EQ(names.size(), 2u);

  Collector<AlignmentQuality> first(nh, "/first/alignment"), second(nh, "/second/alignment");
  ros::Publisher pub1 = nh.advertise<sensor_msgs::PointCloud2>("/first/scan", 10);
  ros::Publisher pub2 = nh.advertise<sensor_msgs::PointCloud2>("/second/scan", 10);
  ASSERT_TRUE(waitForSubscriber(pub1));
  ASSERT_TRUE(waitForSubscriber(pub2));
  ros::WallDuration(1.0).sleep();  // TF connections
  std::mt19937 rng(9);
  const ros::Time base = ros::Time::now();
  // Scans [from, to) of the trajectory to both nodelets, each after its TF.
  auto publishScans = [&](int from, int to) {
    for (int i = from; i < to; ++i) {
      const double t = 0.1 * i;
      const ros::Time stamp = base + ros::Duration(t);
      sendTf(br, trajectory(t), stamp, "lidar");
      ros::WallDuration(0.03).sleep();
      pub1.publish(lidarCloud(trajectory(t), stamp, "lidar", rng, 1));
      pub2.publish(lidarCloud(trajectory(t), stamp, "lidar", rng, 1));
      ros::WallDuration(0.1).sleep();
    }
  };
  publishScans(0, 4);
  ASSERT_TRUE(first.waitFor(3, 15.0));
  ASSERT_TRUE(second.waitFor(3, 15.0));
  for (const auto& m : first.all()) EXPECT_TRUE(m.aligned);
  for (const auto& m : second.all()) EXPECT_TRUE(m.aligned);

  // Unload the first: the second keeps working, the first's outputs disappear.
  nodelet::NodeletUnload un;
  un.request.name = "/first/coral";
  ASSERT_TRUE(ros::service::call("/manager/unload_nodelet", un));
  EXPECT_TRUE(un.response.success);
  ros::WallDuration(1.0).sleep();
  EXPECT_FALSE(topicHasPublisher("/first/alignment"));
  EXPECT_EQ(loaded(), std::vector<std::string>{"/second/coral"});
  const std::size_t before = second.size();
  publishScans(4, 6);
  EXPECT_TRUE(second.waitFor(before + 2, 15.0));

  un.request.name = "/second/coral";
  ASSERT_TRUE(ros::service::call("/manager/unload_nodelet", un));
  EXPECT_TRUE(un.response.success);
  EXPECT_TRUE(loaded().empty());  // the manager is still up and answers
  // Loading again after unloading works (no stale global state).
  EXPECT_TRUE(load("first"));
  EXPECT_EQ(loaded().size(), 1u);
}

TEST(Manager, InvalidParametersFailTheLoad) {
  ros::param::set("/broken/coral/coral/radius", -1.0);
  // onInit rejects the value (FATAL log naming ~coral/radius), so the load fails.
  EXPECT_FALSE(load("broken"));
  const auto names = loaded();
  EXPECT_EQ(std::count(names.begin(), names.end(), "/broken/coral"), 0);
  EXPECT_EQ(names.size(), 1u);  // the manager still runs the nodelet loaded above
}

// Issue 23: a misspelt group (`coarl:`) was ignored and its settings left at the defaults.
// Now the load fails and the FATAL log says why, in the words coral_check uses for the same
// preset.
TEST(Manager, MisspeltGroupFailsTheLoadNamingTheNearestGroup) {
  ros::NodeHandle nh;
  std::mutex mutex;
  std::vector<std::string> logs;
  ros::Subscriber sub =
      nh.subscribe<rosgraph_msgs::Log>("/rosout", 100, [&](const rosgraph_msgs::Log::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(mutex);
        logs.push_back(m->msg);
      });
  // Every node publishes its log on /rosout (the manager's FATAL included): wait for the
  // connections (the manager and this node), so that the message cannot be missed.
  for (int i = 0; i < 100 && sub.getNumPublishers() < 2; ++i) ros::WallDuration(0.1).sleep();
  ros::WallDuration(0.5).sleep();
  ros::param::set("/typo/coral/coarl/radius", 0.5);
  EXPECT_FALSE(load("typo"));
  const auto names = loaded();
  EXPECT_EQ(std::count(names.begin(), names.end(), "/typo/coral"), 0);
  const std::string expected =
      "invalid parameters in /typo/coral: unknown group coarl (did you mean coral?)";
  bool found = false;
  for (int i = 0; i < 100 && !found; ++i) {
    ros::WallDuration(0.1).sleep();
    std::lock_guard<std::mutex> lock(mutex);
    found = std::find(logs.begin(), logs.end(), expected) != logs.end();
  }
  EXPECT_TRUE(found) << "no log \"" << expected << "\"";
}

}  // namespace

// main(): test/rostest/rostest_main.cpp.
const coral_test::RostestNode coral_test::kRostestNode{"nodelet_manager_test", 2};
