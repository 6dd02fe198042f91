// Writes a simulated radar-inertial sequence with ground truth (eval/rio_simulation.hpp)
// in the text format of eval/rio_sequence.hpp:
//   coral_rio_simulate --trajectory handheld|vehicle [--seed N] [--reflectors N]
//                      [--noise-scale K] [--barometer] [--radar-delay S] --output FILE.seq
// (--reflectors overrides the scene's reflector count, --noise-scale multiplies the polar
// point noise, --barometer adds barometer samples: RioSimConfig's baro_* settings,
// --radar-delay stamps each radar frame S seconds before its measurement time.)
#include <iostream>
#include <limits>
#include <string>

#include "coral_introspection/eval/rio_simulation.hpp"
#include "coral_introspection/eval/tool_args.hpp"

using namespace coral_introspection;

namespace {
constexpr const char* kUsage =
    "usage: coral_rio_simulate --trajectory handheld|vehicle [--seed N] [--reflectors N] "
    "[--noise-scale K] [--barometer] [--radar-delay S] --output FILE.seq";
}  // namespace

int main(int argc, char** argv) {
  eval::ToolArgs args;
  if (const auto exit = eval::readCommandLine(
          "coral_rio_simulate", kUsage, argc, argv,
          {"--trajectory", "--seed", "--reflectors", "--noise-scale", "--radar-delay", "--output"},
          {"--barometer"}, &args))
    return *exit;
  std::string err;
  int seed = 1, reflectors = -1;  // reflectors <= 0: the trajectory's own number
  double noise_scale = 1.0, radar_delay = 0.0;
  if (!eval::intOption(args, "--seed", seed, 0, std::numeric_limits<int>::max(), &seed, &err) ||
      !eval::intOption(args, "--reflectors", reflectors, std::numeric_limits<int>::min(),
                       std::numeric_limits<int>::max(), &reflectors, &err) ||
      !eval::numberOption(args, "--noise-scale", noise_scale, &noise_scale, &err) ||
      !eval::numberOption(args, "--radar-delay", radar_delay, &radar_delay, &err))
    return eval::toolError("coral_rio_simulate", err, kUsage);
  const std::string trajectory = args.get("--trajectory", "handheld"),
                    output = args.get("--output");
  const bool barometer = args.flag("--barometer");
  if (output.empty() || (trajectory != "handheld" && trajectory != "vehicle"))
    return eval::toolError("coral_rio_simulate",
                           "--output is required and --trajectory handheld or vehicle", kUsage);
  eval::RioSimConfig cfg = trajectory == "handheld"
                               ? eval::RioSimConfig::handheld(static_cast<unsigned>(seed))
                               : eval::RioSimConfig::vehicle(static_cast<unsigned>(seed));
  if (reflectors > 0) cfg.num_reflectors = reflectors;
  cfg.barometer = barometer;
  cfg.radar_delay = radar_delay;
  cfg.point_noise.sigma_range *= noise_scale;
  cfg.point_noise.sigma_azimuth *= noise_scale;
  cfg.point_noise.sigma_elevation *= noise_scale;
  const eval::RioSequence seq = eval::simulateRio(cfg);
  if (!eval::writeRioSequence(output, seq, &err)) {
    std::cerr << "coral_rio_simulate: " << err << "\n";
    return 1;
  }
  std::cout << "wrote " << seq.imu.size() << " IMU samples, " << seq.radar.size()
            << " radar frames, " << seq.ground_truth.size() << " ground-truth poses, "
            << seq.baro.size() << " barometer samples to " << output << "\n";
  return 0;
}
