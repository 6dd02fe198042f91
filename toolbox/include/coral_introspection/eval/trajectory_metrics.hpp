// Trajectory accuracy as the paper reports it (evo's defaults): APE after an SE(3)
// alignment of the positions (Umeyama, no scale) and per-frame RPE, RMSE of translation
// [m] and rotation [deg]; the loop error of a trajectory that ends where it starts; TUM
// trajectory files ("t x y z qx qy qz qw").
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/eval/rio_sequence.hpp"

namespace coral_introspection {
namespace eval {

struct TrajectoryErrors {
  int pairs = 0;                              // estimate poses matched with ground truth
  double ape_trans = 0.0, ape_rot_deg = 0.0;  // RMSE
  double rpe_trans = 0.0, rpe_rot_deg = 0.0;  // RMSE over consecutive matched poses
};

// Matches each estimated pose with the ground-truth pose nearest in time (within max_dt;
// gt is interpolated linearly / by slerp between its two neighbours). align: SE(3)
// alignment of the matched positions before APE (RPE does not depend on it).
TrajectoryErrors trajectoryErrors(const std::vector<StampedPose>& estimate,
                                  const std::vector<StampedPose>& ground_truth, double max_dt,
                                  bool align);

struct LoopError {
  double horizontal = 0.0, vertical = 0.0;  // [m] last position minus first
  double yaw_deg = 0.0;                     // yaw(last) - yaw(first), wrapped to (-180, 180]
  double x = 0.0, y = 0.0;  // [m] last minus first position in the first pose's heading frame
};
LoopError loopError(const std::vector<StampedPose>& trajectory);

bool writeTum(const std::string& path, const std::vector<StampedPose>& trajectory,
              std::string* error);
bool readTum(const std::string& path, std::vector<StampedPose>* trajectory, std::string* error);

}  // namespace eval
}  // namespace coral_introspection
