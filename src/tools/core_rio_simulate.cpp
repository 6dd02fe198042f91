// Writes a simulated radar-inertial sequence with ground truth (eval/rio_simulation.hpp)
// in the text format of eval/rio_sequence.hpp:
//   coral_rio_simulate --trajectory handheld|vehicle [--seed N] [--reflectors N]
//                      [--noise-scale K] [--barometer] --output FILE.seq
// (--reflectors overrides the scene's reflector count, --noise-scale multiplies the polar
// point noise, --barometer adds barometer samples: RioSimConfig's baro_* settings.)
#include <iostream>
#include <string>

#include "coral_introspection/eval/rio_simulation.hpp"

using namespace coral_introspection;

int main(int argc, char** argv) {
  std::string trajectory = "handheld", output;
  unsigned seed = 1;
  int reflectors = -1;
  double noise_scale = 1.0;
  bool barometer = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const std::string v = i + 1 < argc ? argv[i + 1] : "";
    if (a == "--trajectory") {
      trajectory = v;
      ++i;
    } else if (a == "--seed") {
      seed = static_cast<unsigned>(std::stoul(v));
      ++i;
    } else if (a == "--reflectors") {
      reflectors = std::stoi(v);
      ++i;
    } else if (a == "--noise-scale") {
      noise_scale = std::stod(v);
      ++i;
    } else if (a == "--barometer") {
      barometer = true;
    } else if (a == "--output") {
      output = v;
      ++i;
    } else {
      output.clear();
      break;
    }
  }
  if (output.empty() || (trajectory != "handheld" && trajectory != "vehicle")) {
    std::cerr << "usage: coral_rio_simulate --trajectory handheld|vehicle [--seed N] "
                 "[--reflectors N] [--noise-scale K] [--barometer] --output FILE.seq\n";
    return 2;
  }
  core::RioSimConfig cfg = trajectory == "handheld" ? core::RioSimConfig::handheld(seed)
                                                    : core::RioSimConfig::vehicle(seed);
  if (reflectors > 0) cfg.num_reflectors = reflectors;
  cfg.barometer = barometer;
  cfg.point_noise.sigma_range *= noise_scale;
  cfg.point_noise.sigma_azimuth *= noise_scale;
  cfg.point_noise.sigma_elevation *= noise_scale;
  const core::RioSequence seq = core::simulateRio(cfg);
  std::string err;
  if (!core::writeRioSequence(output, seq, &err)) {
    std::cerr << "coral_rio_simulate: " << err << "\n";
    return 1;
  }
  std::cout << "wrote " << seq.imu.size() << " IMU samples, " << seq.radar.size()
            << " radar frames, " << seq.ground_truth.size() << " ground-truth poses, "
            << seq.baro.size() << " barometer samples to " << output << "\n";
  return 0;
}
