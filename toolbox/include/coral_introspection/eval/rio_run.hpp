// Bookkeeping of one odometry run shared by the runners (rio_offline on a bag,
// coral_rio_run on a text sequence, the evaluation tools): the trajectory (one pose per
// radar frame; frames before the initialisation get the initial pose, the radar stood
// still there), counts and timing, and a printable summary.
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/eval/trajectory_metrics.hpp"
#include "coral_introspection/rio/estimator.hpp"

namespace coral_introspection {
namespace eval {

class RioRun {
 public:
  void add(const std::vector<rio::FrameReport>& reports);
  const std::vector<StampedPose>& trajectory() const { return trajectory_; }
  const std::vector<rio::FrameReport>& reports() const { return reports_; }
  int frames() const { return static_cast<int>(reports_.size()); }
  // Frames processed, resets, median / mean solver time, and with wall_seconds > 0 the
  // time per frame and the real-time factor over `duration` seconds of data.
  std::string summary(double wall_seconds, double duration) const;
  // One CSV line per frame: status, state, counts, solver figures.
  bool writeReports(const std::string& path, std::string* error) const;

 private:
  std::vector<rio::FrameReport> reports_;
  std::vector<StampedPose> trajectory_;
  std::vector<double> waiting_;  // frames before the initialisation
};

// One line: the radar-IMU time offset (estimated, with its prior and bound, or configured).
std::string timeOffsetSummary(const rio::Estimator& est);

}  // namespace eval
}  // namespace coral_introspection
