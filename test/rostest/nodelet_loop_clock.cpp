// rostest: a looping sequence under simulated time (see nodelet_loop_clock.test).
#include "coral_rostest_utils.hpp"
#include "rostest_main.hpp"

#include <rosgraph_msgs/Clock.h>

#include <atomic>
#include <thread>

using namespace coral_test;
using coral_introspection::AlignmentQuality;

namespace {

// Publishes /clock = start + wall time elapsed since start was set (100 Hz).
class SimClock {
 public:
  explicit SimClock(ros::NodeHandle& nh) : pub_(nh.advertise<rosgraph_msgs::Clock>("/clock", 10)) {
    thread_ = std::thread([this] {
      while (run_) {
        rosgraph_msgs::Clock c;
        c.clock = now();
        pub_.publish(c);
        ros::WallDuration(0.01).sleep();
      }
    });
  }
  ~SimClock() {
    run_ = false;
    thread_.join();
  }
  void jumpTo(double t) {
    std::lock_guard<std::mutex> l(mutex_);
    start_ = t;
    wall_ = ros::WallTime::now();
  }
  ros::Time now() {
    std::lock_guard<std::mutex> l(mutex_);
    return ros::Time(start_ + (ros::WallTime::now() - wall_).toSec());
  }

 private:
  ros::Publisher pub_;
  std::mutex mutex_;
  double start_ = 1000.0;
  ros::WallTime wall_ = ros::WallTime::now();
  std::atomic<bool> run_{true};
  std::thread thread_;
};

TEST(LoopWithClock, SecondLoopIsJudgedFromItsFirstPair) {
  ros::NodeHandle nh;
  SimClock clock(nh);
  tf2_ros::TransformBroadcaster br;
  std::mt19937 rng(4);
  Collector<AlignmentQuality> all(nh, "/lidar/alignment", keepAll<AlignmentQuality>);
  ros::Publisher pub = nh.advertise<sensor_msgs::PointCloud2>("/lidar/scan", 10);
  ASSERT_TRUE(waitForSubscriber(pub));
  ros::WallDuration(1.0).sleep();
  for (double loop_start : {1000.0, 900.0}) {  // the bag starts over: time jumps back 100 s
    clock.jumpTo(loop_start);
    ros::WallDuration(0.2).sleep();  // /clock reached everyone
    std::vector<ros::Time> stamps;
    for (int k = 0; k < 4; ++k) {
      const ros::Time stamp = clock.now();
      stamps.push_back(stamp);
      const double t = 0.1 * k;
      sendTf(br, trajectory(t), stamp, "lidar");
      ros::WallDuration(0.03).sleep();
      pub.publish(lidarCloud(trajectory(t), stamp, "lidar", rng, 1));
      ros::WallDuration(0.1).sleep();
    }
    ros::WallDuration(1.0).sleep();
    std::map<uint64_t, AlignmentQuality> by_stamp;
    for (const auto& m : all.all()) by_stamp[m.stamp_b.toNSec()] = m;
    ASSERT_TRUE(by_stamp.count(stamps[1].toNSec())) << "loop at " << loop_start;
    const AlignmentQuality& second = by_stamp[stamps[1].toNSec()];
    EXPECT_EQ(second.status, AlignmentQuality::VERDICT)
        << "loop at " << loop_start << ": " << second.reason;
    EXPECT_EQ(second.stamp_a, stamps[0]);
    for (int k = 2; k < 4; ++k)
      EXPECT_EQ(by_stamp[stamps[k].toNSec()].status, AlignmentQuality::VERDICT)
          << by_stamp[stamps[k].toNSec()].reason;
  }
}

}  // namespace

// main(): test/rostest/rostest_main.cpp.
const coral_test::RostestNode coral_test::kRostestNode{"nodelet_loop_clock_test", 2};
