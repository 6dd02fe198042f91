// Runs the radar-inertial odometry on a plain-text sequence (eval/rio_sequence.hpp), as
// fast as it can, without ROS:
//   coral_rio_run --sequence FILE --config FILE.yaml [--set group/key=value]...
//                 [--output TRAJ.tum] [--report FRAMES.csv] [--loop]
// Prints frames processed and the time per frame; --loop also prints the end-point error
// of a sequence that ends where it starts; ground truth in the sequence gives APE / RPE.
#include <chrono>
#include <iostream>
#include <string>
#include <vector>

#include "coral_introspection/eval/rio_run.hpp"
#include "coral_introspection/rio/config_yaml.hpp"

using namespace coral_introspection;

int main(int argc, char** argv) {
  std::string sequence, config, output, report;
  std::vector<std::string> overrides;
  bool loop = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
    if (a == "--sequence")
      sequence = next();
    else if (a == "--config")
      config = next();
    else if (a == "--output")
      output = next();
    else if (a == "--report")
      report = next();
    else if (a == "--set")
      overrides.push_back(next());
    else if (a == "--loop")
      loop = true;
    else {
      std::cerr
          << "usage: coral_rio_run --sequence FILE --config FILE.yaml "
             "[--set group/key=value]... [--output TRAJ.tum] [--report FRAMES.csv] [--loop]\n";
      return 2;
    }
  }
  if (sequence.empty() || config.empty()) {
    // No config would mean default extrinsics, which no rig has (config_yaml.hpp).
    std::cerr << "coral_rio_run: --sequence and --config are required\n";
    return 2;
  }
  YAML::Node root;
  std::string err;
  try {
    root = YAML::LoadFile(config);
  } catch (const YAML::Exception& e) {
    std::cerr << "coral_rio_run: cannot read " << config << ": " << e.what() << "\n";
    return 1;
  }
  for (const std::string& o : overrides)
    if (!rio::applyOverride(root, o, &err)) {
      std::cerr << "coral_rio_run: " << err << "\n";
      return 2;
    }
  rio::RioConfig cfg;
  if (!rio::loadRioConfig(root, &cfg, &err, {{"ros"}})) {
    std::cerr << "coral_rio_run: invalid config: " << err << "\n";
    return 1;
  }
  core::RioSequence seq;
  if (!core::readRioSequence(sequence, &seq, &err)) {
    std::cerr << "coral_rio_run: " << err << "\n";
    return 1;
  }
  rio::Estimator est(cfg);
  core::RioRun run;
  const auto t0 = std::chrono::steady_clock::now();
  core::replay(
      seq, [&](const rio::ImuSample& s) { run.add(est.addImu(s)); },
      [&](const rio::RadarFrame& f) { run.add(est.addRadar(f)); });
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double duration = seq.imu.empty() ? 0.0 : seq.imu.back().t - seq.imu.front().t;
  std::cout << run.summary(wall, duration);
  if (!output.empty() && !core::writeTum(output, run.trajectory(), &err)) {
    std::cerr << "coral_rio_run: " << err << "\n";
    return 1;
  }
  if (!report.empty() && !run.writeReports(report, &err)) {
    std::cerr << "coral_rio_run: " << err << "\n";
    return 1;
  }
  if (loop) {
    const core::LoopError e = core::loopError(run.trajectory());
    std::cout << "loop end-point error: horizontal " << e.horizontal << " m, vertical "
              << e.vertical << " m, yaw " << e.yaw_deg << " deg\n";
  }
  if (!seq.ground_truth.empty()) {
    const core::TrajectoryErrors e =
        core::trajectoryErrors(run.trajectory(), seq.ground_truth, 0.02, true);
    std::cout << "APE RMSE: " << e.ape_trans << " m, " << e.ape_rot_deg
              << " deg; RPE RMSE: " << e.rpe_trans << " m, " << e.rpe_rot_deg << " deg (" << e.pairs
              << " poses)\n";
  }
  return 0;
}
