// Streams a real lidar frame into a running CoralNodelet at sensor rate (or watches a
// stream someone else plays, e.g. `rosbag play -l`) and prints what the nodelet makes of
// it: verdicts per second, latency quantiles, dropped scans, TF failures, memory.
//   rosrun coral_introspection coral_stream_bench --cloud <frame.bin|.pcd> --rate 10
//       --duration 60 [--stride 1] [--pid-of /coral_manager]      (publish + measure)
//   rosrun coral_introspection coral_stream_bench --monitor --duration 1800   (soak)
// The nodelet must run with the same fixed frame and input topic (see --help); it is
// subscribed lazily, so the tool's subscription to `alignment` starts its input.
#include <ros/ros.h>

#include <cstdio>
#include <cstdlib>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "coral_introspection/eval/cloud_io.hpp"
#include "coral_introspection/eval/tool_args.hpp"
#include "coral_introspection/ros_eval/stream_bench.hpp"

namespace ros_eval = coral_introspection::ros_eval;
namespace eval = coral_introspection::eval;
using coral_introspection::AlignmentQuality;

namespace {

struct Args {
  ros_eval::StreamOptions stream;
  std::string cloud, alignment = "alignment", node = "coral", pid_of = "/coral_manager";
  double duration = 60.0, warmup = 3.0, report = 10.0, settle = 2.0;
  bool monitor = false;
};

constexpr const char* kUsage =
    "usage: coral_stream_bench [--cloud FILE] [options]\n"
    "  --cloud FILE        lidar frame (.bin KITTI/VoD, .pcd, .csv) streamed from a moving "
    "sensor\n"
    "  --monitor           publish nothing: measure a stream fed by someone else (soak)\n"
    "  --rate HZ           clouds per second (10)\n"
    "  --duration S        measuring time (60)   --warmup S  not measured (3)\n"
    "  --report S          interim line every S seconds (10)\n"
    "  --settle S          wait for the last verdicts after the stream (2)\n"
    "  --stride K          keep every K-th point of the frame (1)\n"
    "  --noise M           Gaussian noise per coordinate [m] (0.01)\n"
    "  --speed M/S (5)  --yaw-rate RAD/S (0.1)  sensor motion\n"
    "  --topic T (scan)  --frame F (velodyne)  --fixed-frame F (odom)\n"
    "  --alignment T       verdict topic (alignment)\n"
    "  --node NAME         nodelet name in /diagnostics (coral)\n"
    "  --pid-of NODE       ROS node whose memory is reported (/coral_manager)";

int fail(const std::string& msg) { return eval::toolError("coral_stream_bench", msg, kUsage); }

// The status main() returns now (0 after --help), or nothing to go on with *a.
std::optional<int> parse(int argc, char** argv, Args* a) {
  eval::ToolArgs args;
  std::string err;
  const std::vector<std::string> strings = {"--cloud",     "--topic", "--frame", "--fixed-frame",
                                            "--alignment", "--node",  "--pid-of"};
  const std::vector<std::pair<std::string, double*>> numbers = {
      {"--rate", &a->stream.rate},   {"--duration", &a->duration},
      {"--warmup", &a->warmup},      {"--report", &a->report},
      {"--settle", &a->settle},      {"--noise", &a->stream.noise},
      {"--speed", &a->stream.speed}, {"--yaw-rate", &a->stream.yaw_rate}};
  std::vector<std::string> options = strings;
  options.push_back("--stride");
  for (const auto& [name, value] : numbers) options.push_back(name);
  if (const auto exit = eval::readCommandLine("coral_stream_bench", kUsage, argc, argv, options,
                                              {"--monitor"}, &args))
    return *exit;
  for (const auto& [name, value] : numbers)
    if (!eval::numberOption(args, name, *value, value, &err)) return fail(err);
  if (!eval::intOption(args, "--stride", a->stream.stride, std::numeric_limits<int>::min(),
                       std::numeric_limits<int>::max(), &a->stream.stride, &err))
    return fail(err);
  a->monitor = args.flag("--monitor");
  a->cloud = args.get("--cloud", a->cloud);
  a->stream.topic = args.get("--topic", a->stream.topic);
  a->stream.frame = args.get("--frame", a->stream.frame);
  a->stream.fixed_frame = args.get("--fixed-frame", a->stream.fixed_frame);
  a->alignment = args.get("--alignment", a->alignment);
  a->node = args.get("--node", a->node);
  a->pid_of = args.get("--pid-of", a->pid_of);
  if (!a->monitor && a->cloud.empty()) return fail("--cloud FILE or --monitor is required");
  if (!(a->stream.rate > 0.0 && a->duration > 0.0 && a->report > 0.0 && a->stream.stride >= 1))
    return fail("--rate, --duration, --report must be > 0 and --stride >= 1");
  return std::nullopt;
}

unsigned long counter(const std::map<std::string, std::string>& d, const std::string& key) {
  const auto it = d.find(key);
  return it == d.end() ? 0ul : std::strtoul(it->second.c_str(), nullptr, 10);
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "coral_stream_bench", ros::init_options::AnonymousName);
  Args a;
  if (const auto exit = parse(argc, argv, &a)) return *exit;
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ros_eval::VerdictMonitor monitor(nh, a.alignment, a.node);

  std::unique_ptr<ros_eval::CloudStreamer> streamer;
  if (!a.monitor) {
    eval::LoadedCloud cloud;
    std::string err;
    if (!eval::loadCloud(a.cloud, &cloud, &err)) {
      std::fprintf(stderr, "coral_stream_bench: %s\n", err.c_str());
      return 1;
    }
    streamer = std::make_unique<ros_eval::CloudStreamer>(nh, cloud.points, a.stream);
    if (!streamer->waitForSubscriber(20.0)) {
      std::fprintf(stderr, "coral_stream_bench: nobody subscribes %s (is the nodelet running?)\n",
                   nh.resolveName(a.stream.topic).c_str());
      return 1;
    }
    std::printf("streaming %s: %zu points per cloud at %.1f Hz for %.0f s (+%.0f s warm-up)\n",
                a.cloud.c_str(), streamer->points(), a.stream.rate, a.duration, a.warmup);
  } else {
    std::printf("monitoring %s for %.0f s (+%.0f s warm-up)\n", nh.resolveName(a.alignment).c_str(),
                a.duration, a.warmup);
  }
  std::fflush(stdout);
  auto wait = [&](double s) {
    if (streamer)
      streamer->run(s);
    else
      ros::WallDuration(s).sleep();
  };
  wait(a.warmup);

  const std::optional<int> pid = ros_eval::nodePid(a.pid_of);
  if (!pid) std::printf("(no memory figures: node %s not found)\n", a.pid_of.c_str());
  auto rss = [&] { return pid ? ros_eval::processRssMiB(*pid) : 0.0; };
  monitor.reset();
  const auto diag0 = monitor.diagnostics();
  const double rss0 = rss();
  double rss_max = rss0;
  const ros::WallTime start = ros::WallTime::now();
  for (double t = 0.0; t < a.duration - 1e-9 && ros::ok();) {
    const double step = std::min(a.report, a.duration - t);
    wait(step);
    t += step;
    const ros_eval::StreamSummary s = monitor.summary();
    const double r = rss();
    rss_max = std::max(rss_max, r);
    const auto d = monitor.diagnostics();
    std::printf(
        "t = %6.0f s: %.2f verdicts/s, latency median %.3f s p95 %.3f s, dropped %lu, tf "
        "failures %lu, RSS %.1f MiB",
        t, s.verdicts / t, s.latency_median, s.latency_p95,
        counter(d, "scans dropped (worker busy)") - counter(diag0, "scans dropped (worker busy)"),
        counter(d, "tf failures") - counter(diag0, "tf failures"), r);
    if (s.loops > 0) std::printf(", loops judged %zu/%zu", s.loops_judged, s.loops);
    std::printf("\n");
    std::fflush(stdout);
  }
  const double measured = (ros::WallTime::now() - start).toSec();
  ros::WallDuration(a.settle).sleep();  // last verdicts and one more diagnostics report
  const ros_eval::StreamSummary s = monitor.summary();
  const auto d = monitor.diagnostics();
  const double rss1 = rss();
  auto delta = [&](const char* key) { return counter(d, key) - counter(diag0, key); };

  std::printf("\n== coral_stream_bench: %.0f s measured ==\n", measured);
  std::printf("messages on %s: %zu (", nh.resolveName(a.alignment).c_str(), s.messages);
  const char* names[] = {"verdict", "invalid pair", "not paired", "no pose", "refused", "dropped"};
  bool first = true;
  for (const auto& [status, n] : s.by_status) {
    std::printf("%s%s %zu", first ? "" : ", ", status < 6 ? names[status] : "?", n);
    first = false;
  }
  std::printf("); without a verdict and without a reason: %zu\n", s.without_reason);
  std::printf("verdicts/s:            %.2f (CorAl ran: %.2f pairs/s)\n", s.verdicts / measured,
              s.judged / measured);
  std::printf(
      "latency (arrival -> publication, AlignmentQuality.latency): median %.3f s, p95 "
      "%.3f s, max %.3f s\n",
      s.latency_median, s.latency_p95, s.latency_max);
  if (streamer)
    std::printf("age (scan stamp -> received here, judged scans): median %.3f s, p95 %.3f s\n",
                s.age_median, s.age_p95);
  std::printf(
      "nodelet counters (delta): received %lu, dropped (worker busy) %lu, tf failures "
      "%lu, late %lu, lost upstream %lu, over time budget %lu\n",
      delta("scans received"), delta("scans dropped (worker busy)"), delta("tf failures"),
      delta("late scans (TF after tf_timeout)"), delta("scans lost upstream (seq gaps)"),
      delta("scans over time budget"));
  std::printf("diagnostics: %s\n", d.count("__message") ? d.at("__message").c_str() : "(none)");
  if (pid)
    std::printf("RSS of %s (pid %d): start %.1f MiB, end %.1f MiB (%+.1f %%), max %.1f MiB\n",
                a.pid_of.c_str(), *pid, rss0, rss1, rss0 > 0 ? 100.0 * (rss1 / rss0 - 1.0) : 0.0,
                std::max(rss_max, rss1));
  if (s.loops > 0)
    std::printf("loops judged after their first scan: %zu / %zu%s%s\n", s.loops_judged, s.loops,
                s.worst_loop.empty() ? "" : "; first failing: ", s.worst_loop.c_str());
  return 0;
}
