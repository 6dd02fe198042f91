// Runs the radar-inertial odometry on a plain-text sequence (eval/rio_sequence.hpp), as
// fast as it can, without ROS:
//   coral_rio_run --sequence FILE --config FILE.yaml [--set group/key=value]...
//                 [--output TRAJ.tum] [--report FRAMES.csv] [--loop]
// Prints frames processed and the time per frame; --loop also prints the end-point error
// of a sequence that ends where it starts; ground truth in the sequence gives APE / RPE and
// the vertical APE (gauge-free: both frames are gravity-aligned, heights taken relative to
// the first pose). Barometer samples of the sequence are fed when barometer/enabled is set.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "coral_introspection/config/yaml_tree.hpp"
#include "coral_introspection/eval/rio_run.hpp"
#include "coral_introspection/eval/tool_args.hpp"
#include "coral_introspection/rio/config_yaml.hpp"

using namespace coral_introspection;

namespace {

// RMSE of (z - z_first) - (z_gt - z_gt_first) over the estimated poses, ground truth
// interpolated linearly in time (the odometry's vertical drift; no alignment needed).
double verticalApe(const std::vector<eval::StampedPose>& est,
                   const std::vector<eval::StampedPose>& gt) {
  auto gt_z = [&gt](double t) {
    std::size_t k = 1;
    while (k + 1 < gt.size() && gt[k].t < t) ++k;
    const double u = std::clamp((t - gt[k - 1].t) / (gt[k].t - gt[k - 1].t), 0.0, 1.0);
    return gt[k - 1].p.z() + u * (gt[k].p.z() - gt[k - 1].p.z());
  };
  if (est.empty() || gt.size() < 2) return 0.0;
  const double z0 = est.front().p.z(), g0 = gt_z(est.front().t);
  double sum = 0.0;
  for (const eval::StampedPose& p : est) {
    const double e = (p.p.z() - z0) - (gt_z(p.t) - g0);
    sum += e * e;
  }
  return std::sqrt(sum / est.size());
}

constexpr const char* kUsage =
    "usage: coral_rio_run --sequence FILE --config FILE.yaml [--set group/key=value]... "
    "[--output TRAJ.tum] [--report FRAMES.csv] [--loop]";

}  // namespace

int main(int argc, char** argv) {
  eval::ToolArgs args;
  if (const auto exit = eval::readCommandLine(
          "coral_rio_run", kUsage, argc, argv,
          {"--sequence", "--config", "--output", "--report", "--set"}, {"--loop"}, &args))
    return *exit;
  const std::string sequence = args.get("--sequence"), config = args.get("--config"),
                    output = args.get("--output"), report = args.get("--report");
  const std::vector<std::string> overrides = args.all("--set");
  const bool loop = args.flag("--loop");
  // No config would mean default extrinsics, which no rig has (config_yaml.hpp).
  if (sequence.empty() || config.empty())
    return eval::toolError("coral_rio_run", "--sequence and --config are required", kUsage);
  config::ParamTree tree;
  std::string err;
  if (!config::loadYamlFile(config, &tree, &err)) {
    std::cerr << "coral_rio_run: " << err << "\n";
    return 1;
  }
  for (const std::string& o : overrides)
    if (!rio::applyOverride(tree, o, &err)) {
      std::cerr << "coral_rio_run: " << err << "\n";
      return 2;
    }
  rio::RioConfig cfg;
  if (!rio::loadRioConfig(tree, &cfg, &err, {{"ros"}})) {
    std::cerr << "coral_rio_run: invalid config: " << err << "\n";
    return 1;
  }
  eval::RioSequence seq;
  if (!eval::readRioSequence(sequence, &seq, &err)) {
    std::cerr << "coral_rio_run: " << err << "\n";
    return 1;
  }
  rio::Estimator est(cfg);
  eval::RioRun run;
  const auto t0 = std::chrono::steady_clock::now();
  eval::replay(
      seq, [&](const rio::ImuSample& s) { run.add(est.addImu(s)); },
      [&](const rio::RadarFrame& f) { run.add(est.addRadar(f)); },
      [&](const rio::BaroSample& b) { est.addBaro(b); });
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double duration = seq.imu.empty() ? 0.0 : seq.imu.back().t - seq.imu.front().t;
  std::cout << run.summary(wall, duration);
  std::cout << eval::timeOffsetSummary(est);
  if (!output.empty() && !eval::writeTum(output, run.trajectory(), &err)) {
    std::cerr << "coral_rio_run: " << err << "\n";
    return 1;
  }
  if (!report.empty() && !run.writeReports(report, &err)) {
    std::cerr << "coral_rio_run: " << err << "\n";
    return 1;
  }
  if (loop) {
    const eval::LoopError e = eval::loopError(run.trajectory());
    std::cout << "loop end-point error: horizontal " << e.horizontal << " m, vertical "
              << e.vertical << " m, yaw " << e.yaw_deg << " deg\n";
  }
  if (!seq.ground_truth.empty()) {
    const eval::TrajectoryErrors e =
        eval::trajectoryErrors(run.trajectory(), seq.ground_truth, 0.02, true);
    std::cout << "APE RMSE: " << e.ape_trans << " m, " << e.ape_rot_deg
              << " deg; RPE RMSE: " << e.rpe_trans << " m, " << e.rpe_rot_deg << " deg (" << e.pairs
              << " poses)\n";
    std::cout << "vertical APE RMSE: " << verticalApe(run.trajectory(), seq.ground_truth) << " m\n";
  }
  return 0;
}
