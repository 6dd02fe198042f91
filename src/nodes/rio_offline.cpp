// Pinned offline runner of the radar-inertial odometry on a bag, as fast as it can (no
// clock, no master):
//   rosrun coral_introspection rio_offline --bag FILE --config FILE.yaml --output TRAJ.tum
//                                          [--set group/key=value]... [--report FRAMES.csv]
// Writes one line "t x y z qx qy qz qw" per radar frame (body = IMU frame in the odometry
// frame) and prints frames processed, time per frame, the real-time factor and the loop
// end-point error (meaningful for a recording that ends where it starts, like the TI bag).
// Topics and the radar time source come from the YAML's `ros` group (ros/rio_input.hpp).
//
// Refuse, don't guess: input that cannot give a trajectory (a config error, a topic missing
// from the bag, scans without the radial-velocity field, IMU units that cannot be right,
// IMU and radar clocks that do not overlap, no odometry at all, an odometry that mostly
// reset) ends with exit status 1 and the reason on stderr; no trajectory and no end-point
// figure are written then. Usage errors: exit status 2.
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/FluidPressure.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "coral_introspection/config/yaml_tree.hpp"
#include "coral_introspection/coral/statistics.hpp"
#include "coral_introspection/eval/rio_run.hpp"
#include "coral_introspection/eval/tool_args.hpp"
#include "coral_introspection/rio/config_yaml.hpp"
#include "coral_introspection/ros/rio_input.hpp"

using namespace coral_introspection;

namespace {

// Empty when the bag has `topic` with message type `type`; else why not (the setting to
// change, the nearest topic of that type).
std::string checkTopic(const std::map<std::string, std::string>& topics, const std::string& topic,
                       const std::string& type, const std::string& setting) {
  const auto it = topics.find(topic);
  if (it != topics.end())
    return it->second == type
               ? ""
               : "topic " + topic + " (ros/" + setting + ") is " + it->second + ", not " + type;
  std::vector<std::string> same_type;
  for (const auto& [name, t] : topics)
    if (t == type) same_type.push_back(name);
  std::string list;
  for (const std::string& n : same_type) list += (list.empty() ? "" : ", ") + n;
  return "the bag has no topic '" + topic + "' (ros/" + setting + ")" +
         config::didYouMean(topic, same_type) + "; its " + type +
         " topics: " + (list.empty() ? "none" : list);
}

std::string checkTopics(rosbag::Bag& bag, const ros_adapters::RioInputConfig& in, bool baro) {
  rosbag::View all(bag);
  if (all.size() == 0) return "the bag has no messages";
  std::map<std::string, std::string> topics;
  for (const rosbag::ConnectionInfo* c : all.getConnections()) topics[c->topic] = c->datatype;
  std::string why = checkTopic(topics, in.imu_topic, "sensor_msgs/Imu", "imu_topic");
  if (why.empty())
    why = checkTopic(topics, in.radar_topic, "sensor_msgs/PointCloud2", "radar_topic");
  if (why.empty() && in.time_source == "trigger")
    why = checkTopic(topics, in.trigger_topic, "std_msgs/Header", "trigger_topic");
  if (why.empty() && baro)  // barometer/enabled: its topic must be there too
    why = checkTopic(topics, in.baro_topic, "sensor_msgs/FluidPressure", "baro_topic");
  return why;
}

// Time span of one sensor's stamps.
struct Span {
  long n = 0;
  double first = 0.0, last = 0.0;
  void add(double t) {
    first = n++ == 0 ? t : std::min(first, t);
    last = std::max(last, t);
  }
};

// Half the radar's span without IMU: the clocks differ (or the stamps are not times). Judged
// first, also over the part read before another refusal: it names the cause of that one (an
// IMU 100 s late is refused by the time offset check at arrival too).
std::string judgeClocks(const Span& imu, const Span& radar) {
  if (imu.n == 0 || radar.n == 0) return "";
  const double overlap = std::min(imu.last, radar.last) - std::max(imu.first, radar.first);
  if (overlap >= 0.5 * (radar.last - radar.first)) return "";
  return "the IMU and radar clocks do not overlap: IMU stamps " + std::to_string(imu.first) +
         " .. " + std::to_string(imu.last) + " s, radar frames " + std::to_string(radar.first) +
         " .. " + std::to_string(radar.last) + " s";
}

// After the run: why its trajectory is not one ("" when it is).
std::string judgeRun(const Span& imu, const Span& radar, const eval::RioRun& run,
                     const std::string& last_input_error) {
  const std::string why = last_input_error.empty() ? "" : " (last: " + last_input_error + ")";
  if (imu.n == 0) return "no usable IMU sample" + why;
  if (radar.n == 0) return "no radar frame" + why;
  long tracked = 0, resets = 0;
  std::string last_message;
  for (const rio::FrameReport& r : run.reports()) {
    tracked += r.status == rio::FrameStatus::kTracking;
    resets += r.status == rio::FrameStatus::kReset;
    if (!r.message.empty()) last_message = r.message;
  }
  if (tracked == 0)
    return "no odometry: none of the " + std::to_string(run.frames()) +
           " radar frames was tracked (last: " + last_message + ")";
  if (2 * resets > run.frames())
    return "the odometry reset on " + std::to_string(resets) + " of " +
           std::to_string(run.frames()) + " frames (last: " + last_message + ")";
  return "";
}

constexpr const char* kUsage =
    "usage: rio_offline --bag FILE --config FILE.yaml --output TRAJ.tum "
    "[--set group/key=value]... [--report FRAMES.csv]";

int refuse(const std::string& why) {
  std::cerr << "rio_offline: refused: " << why << "; no trajectory written\n";
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  eval::ToolArgs args;
  if (const auto exit =
          eval::readCommandLine("rio_offline", kUsage, argc, argv,
                                {"--bag", "--config", "--output", "--report", "--set"}, {}, &args))
    return *exit;
  const std::string bag_path = args.get("--bag"), config = args.get("--config"),
                    output = args.get("--output"), report = args.get("--report");
  const std::vector<std::string> overrides = args.all("--set");
  if (bag_path.empty() || config.empty() || output.empty())
    return eval::toolError("rio_offline", "--bag, --config and --output are required", kUsage);
  config::ParamTree tree;
  std::string err;
  if (!config::loadYamlFile(config, &tree, &err)) return refuse("invalid config: " + err);
  for (const std::string& o : overrides)
    if (!rio::applyOverride(tree, o, &err)) {
      std::cerr << "rio_offline: " << err << "\n";
      return 2;
    }
  rio::RioConfig cfg;
  ros_adapters::RioInputConfig in_cfg;
  // Messages name the file and line themselves ("file:line: unknown group ...").
  if (!rio::loadRioConfig(tree, &cfg, &err, {{"ros"}}) ||
      !ros_adapters::loadRioInputConfig(tree, &in_cfg, &err))
    return refuse("invalid config: " + err);

  rosbag::Bag bag;
  try {
    bag.open(bag_path, rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    return refuse("cannot open " + bag_path + ": " + e.what());
  }
  const std::string topic_problem = checkTopics(bag, in_cfg, cfg.barometer.enabled);
  if (!topic_problem.empty()) return refuse(bag_path + ": " + topic_problem);
  std::vector<std::string> topics = {in_cfg.imu_topic, in_cfg.radar_topic};
  if (!in_cfg.trigger_topic.empty()) topics.push_back(in_cfg.trigger_topic);
  if (cfg.barometer.enabled) topics.push_back(in_cfg.baro_topic);
  rosbag::View view(bag, rosbag::TopicQuery(topics));

  rio::Estimator est(cfg);
  ros_adapters::RioInput input(in_cfg);
  eval::RioRun run;
  Span imu_span, radar_span;
  // Newest IMU stamp minus the frame time when a frame completes: the radar's latency on a
  // common clock (TI bag: 0.12 s) plus any clock offset; with time_offset/estimate the
  // estimator judges it (time_offset/max_latency, max_abs) and refuses an offset beyond.
  std::vector<double> arrival_lag;
  std::string last_input_error, refusal;
  auto feed = [&](std::vector<rio::RadarFrame> frames) {
    for (rio::RadarFrame& f : frames) {
      radar_span.add(f.t);
      if (imu_span.n > 0) arrival_lag.push_back(imu_span.last - f.t);
      run.add(est.addRadar(std::move(f)));
    }
  };
  long messages = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (const rosbag::MessageInstance& m : view) {
    try {
      if (m.getTopic() == in_cfg.imu_topic) {
        sensor_msgs::Imu::ConstPtr msg = m.instantiate<sensor_msgs::Imu>();
        rio::ImuSample s;
        if (!msg || !input.imu(*msg, &s, &err)) {
          last_input_error = err;
          continue;
        }
        imu_span.add(s.t);
        run.add(est.addImu(s));
      } else if (m.getTopic() == in_cfg.radar_topic) {
        sensor_msgs::PointCloud2::ConstPtr msg = m.instantiate<sensor_msgs::PointCloud2>();
        if (!msg) continue;
        feed(input.radar(*msg, &err));
        if (!err.empty()) last_input_error = err;
        // A driver gives the field in every scan or in none: the first missing one decides.
        if (input.counters().no_velocity_field > 0) refusal = in_cfg.radar_topic + ": " + err;
      } else if (cfg.barometer.enabled && m.getTopic() == in_cfg.baro_topic) {
        sensor_msgs::FluidPressure::ConstPtr msg = m.instantiate<sensor_msgs::FluidPressure>();
        rio::BaroSample s;
        if (!msg || !input.baro(*msg, &s, &err)) {
          last_input_error = err;
          continue;
        }
        est.addBaro(s);
      } else if (in_cfg.time_source == "trigger" && m.getTopic() == in_cfg.trigger_topic) {
        std_msgs::Header::ConstPtr msg = m.instantiate<std_msgs::Header>();
        if (!msg) continue;
        feed(input.trigger(*msg));
      }
      ++messages;
    } catch (const std::exception& e) {  // a malformed bag message: skip it
      std::cerr << "rio_offline: skipped a message on " << m.getTopic() << ": " << e.what() << "\n";
    }
    if (refusal.empty()) refusal = est.inputError();
    if (!refusal.empty()) break;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << "messages read: " << messages << "\n"
            << run.summary(wall, imu_span.last - imu_span.first);
  const rio::RioCounters& c = est.counters();
  const ros_adapters::RioInputCounters& ic = input.counters();
  std::cout << "counters: failed solves " << c.failed_solves << ", imu gaps " << c.imu_gaps
            << " (bridged with Doppler " << c.gap_bridged << "), time jumps " << c.time_jumps
            << ", empty scans " << c.empty_scans << ", scans without Doppler "
            << c.no_doppler + ic.no_velocity_field << ", unmatched scans "
            << ic.unmatched_scans + input.waitingScans() << "\n";
  std::cout << eval::timeOffsetSummary(est);
  if (cfg.barometer.enabled)
    std::cout << "barometer: frames with a residual " << c.baro_frames << ", bad samples "
              << c.bad_baro + ic.bad_baro << "\n";
  if (!arrival_lag.empty())
    std::cout << "radar frame time vs newest IMU stamp at arrival: median "
              << coral::quantile(arrival_lag, 0.5)  // a measured lag (upper middle)
              << " s (radar latency plus any clock offset)\n";
  if (const std::string clocks = judgeClocks(imu_span, radar_span); !clocks.empty())
    refusal = clocks;
  if (refusal.empty()) refusal = judgeRun(imu_span, radar_span, run, last_input_error);
  if (!refusal.empty()) return refuse(refusal);
  if (!eval::writeTum(output, run.trajectory(), &err) ||
      (!report.empty() && !run.writeReports(report, &err))) {
    std::cerr << "rio_offline: " << err << "\n";
    return 1;
  }
  const eval::LoopError e = eval::loopError(run.trajectory());
  std::cout << "loop end-point error: horizontal " << e.horizontal << " m, vertical " << e.vertical
            << " m, yaw " << e.yaw_deg << " deg; end (x, y) in the start-heading frame (" << e.x
            << ", " << e.y << ") m\n";
  return 0;
}
