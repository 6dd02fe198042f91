// Pinned offline runner of the radar-inertial odometry on a bag, as fast as it can (no
// clock, no master):
//   rosrun coral_introspection rio_offline --bag FILE --config FILE.yaml --output TRAJ.tum
//                                          [--set group/key=value]... [--report FRAMES.csv]
// Writes one line "t x y z qx qy qz qw" per radar frame (body = IMU frame in the odometry
// frame) and prints frames processed, time per frame, the real-time factor and the loop
// end-point error (meaningful for a recording that ends where it starts, like the TI bag).
// Topics and the radar time source come from the YAML's `ros` group (ros/rio_input.hpp).
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>

#include <chrono>
#include <iostream>
#include <string>
#include <vector>

#include "coral_introspection/eval/rio_run.hpp"
#include "coral_introspection/rio/config_yaml.hpp"
#include "coral_introspection/ros/rio_input.hpp"

using namespace coral_introspection;

int main(int argc, char** argv) {
  std::string bag_path, config, output, report;
  std::vector<std::string> overrides;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
    if (a == "--bag")
      bag_path = next();
    else if (a == "--config")
      config = next();
    else if (a == "--output")
      output = next();
    else if (a == "--report")
      report = next();
    else if (a == "--set")
      overrides.push_back(next());
    else {
      std::cerr << "usage: rio_offline --bag FILE --config FILE.yaml --output TRAJ.tum "
                   "[--set group/key=value]... [--report FRAMES.csv]\n";
      return 2;
    }
  }
  if (bag_path.empty() || config.empty() || output.empty()) {
    std::cerr << "rio_offline: --bag, --config and --output are required\n";
    return 2;
  }
  YAML::Node root;
  std::string err;
  try {
    root = YAML::LoadFile(config);
  } catch (const YAML::Exception& e) {
    std::cerr << "rio_offline: cannot read " << config << ": " << e.what() << "\n";
    return 1;
  }
  for (const std::string& o : overrides)
    if (!rio::applyOverride(root, o, &err)) {
      std::cerr << "rio_offline: " << err << "\n";
      return 2;
    }
  rio::RioConfig cfg;
  ros_adapters::RioInputConfig in_cfg;
  std::vector<std::string> warnings;
  if (!rio::loadRioConfig(root, &cfg, &err, &warnings, {"ros"}) ||
      !ros_adapters::loadRioInputConfig(root["ros"], &in_cfg, &err)) {
    std::cerr << "rio_offline: invalid config: " << err << "\n";
    return 1;
  }
  for (const std::string& w : warnings) std::cerr << "warning: " << w << "\n";

  rosbag::Bag bag;
  try {
    bag.open(bag_path, rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    std::cerr << "rio_offline: cannot open " << bag_path << ": " << e.what() << "\n";
    return 1;
  }
  std::vector<std::string> topics = {in_cfg.imu_topic, in_cfg.radar_topic};
  if (!in_cfg.trigger_topic.empty()) topics.push_back(in_cfg.trigger_topic);
  rosbag::View view(bag, rosbag::TopicQuery(topics));

  rio::Estimator est(cfg);
  ros_adapters::RioInput input(in_cfg);
  core::RioRun run;
  double t_first = 0.0, t_last = 0.0;
  long messages = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (const rosbag::MessageInstance& m : view) {
    try {
      if (m.getTopic() == in_cfg.imu_topic) {
        sensor_msgs::Imu::ConstPtr msg = m.instantiate<sensor_msgs::Imu>();
        rio::ImuSample s;
        if (!msg || !input.imu(*msg, &s, &err)) continue;
        if (t_first == 0.0) t_first = s.t;
        t_last = s.t;
        run.add(est.addImu(s));
      } else if (m.getTopic() == in_cfg.radar_topic) {
        sensor_msgs::PointCloud2::ConstPtr msg = m.instantiate<sensor_msgs::PointCloud2>();
        if (!msg) continue;
        for (rio::RadarFrame& f : input.radar(*msg, &err)) run.add(est.addRadar(std::move(f)));
      } else if (in_cfg.time_source == "trigger" && m.getTopic() == in_cfg.trigger_topic) {
        std_msgs::Header::ConstPtr msg = m.instantiate<std_msgs::Header>();
        if (!msg) continue;
        for (rio::RadarFrame& f : input.trigger(*msg)) run.add(est.addRadar(std::move(f)));
      }
      ++messages;
    } catch (const std::exception& e) {  // a malformed bag message: skip it
      std::cerr << "rio_offline: skipped a message on " << m.getTopic() << ": " << e.what() << "\n";
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << "messages read: " << messages << "\n" << run.summary(wall, t_last - t_first);
  const rio::RioCounters& c = est.counters();
  const ros_adapters::RioInputCounters& ic = input.counters();
  std::cout << "counters: failed solves " << c.failed_solves << ", imu gaps " << c.imu_gaps
            << ", time jumps " << c.time_jumps << ", empty scans " << c.empty_scans
            << ", scans without Doppler " << c.no_doppler << ", unmatched scans "
            << ic.unmatched_scans + input.waitingScans() << "\n";
  if (!core::writeTum(output, run.trajectory(), &err) ||
      (!report.empty() && !run.writeReports(report, &err))) {
    std::cerr << "rio_offline: " << err << "\n";
    return 1;
  }
  const core::LoopError e = core::loopError(run.trajectory());
  std::cout << "loop end-point error: horizontal " << e.horizontal << " m, vertical " << e.vertical
            << " m, yaw " << e.yaw_deg << " deg\n";
  return 0;
}
