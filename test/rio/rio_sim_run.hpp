// Shared by the rio tests that run the odometry on a simulated sequence
// (eval/rio_simulation.hpp): the estimator's settings for the simulator's rig and a run that
// collects every frame report.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "coral_introspection/eval/rio_simulation.hpp"
#include "coral_introspection/rio/estimator.hpp"

namespace rio_test {

using namespace coral_introspection;

struct SimRun {
  std::vector<rio::FrameReport> reports;
  rio::RioCounters counters;
  std::string input_error;
  double time_offset = 0.0;  // [s] the estimator's t_d at the end
  long tracked() const {
    long n = 0;
    for (const auto& r : reports) n += r.status == rio::FrameStatus::kTracking;
    return n;
  }
};

// The defaults with the simulator's extrinsics and true point noise.
inline rio::RioConfig simConfig(const eval::RioSimConfig& sim) {
  rio::RioConfig cfg;
  cfg.extrinsics = sim.extrinsics;
  cfg.uncertainty.noise = sim.point_noise;
  return cfg;
}

// Runs the estimator; `feed` gives it the sequence (default: in time order, eval::replay).
inline SimRun runSim(
    const rio::RioConfig& cfg, const eval::RioSequence& seq,
    const std::function<void(rio::Estimator&,
                             const std::function<void(const std::vector<rio::FrameReport>&)>&)>&
        feed = nullptr) {
  rio::Estimator est(cfg);
  SimRun out;
  const auto add = [&](const std::vector<rio::FrameReport>& r) {
    out.reports.insert(out.reports.end(), r.begin(), r.end());
  };
  if (feed)
    feed(est, add);
  else
    eval::replay(
        seq, [&](const rio::ImuSample& s) { add(est.addImu(s)); },
        [&](const rio::RadarFrame& f) { add(est.addRadar(f)); });
  out.counters = est.counters();
  out.input_error = est.inputError();
  out.time_offset = est.timeOffset();
  return out;
}

}  // namespace rio_test
