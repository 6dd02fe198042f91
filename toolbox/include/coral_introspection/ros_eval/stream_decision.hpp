// The preset's stream verdict as an eval::LoopDecision: what the package says of an odometry
// step, the decision the scan-matching front ends keep a registered step by
// (eval::scanMatchedSteps: coral_pose_graph --front_end, coral_loop_eval --calibrate_odometry).
#pragma once

#include <vector>

#include "coral_introspection/eval/incremental_loops.hpp"
#include "coral_introspection/online/introspector_config.hpp"

namespace coral_introspection {
namespace ros_eval {

// Accepts candidate c when online::judgePair on scans[c.a], scans[c.b] at c.T_a_b gives a valid
// verdict that says aligned (cfg's stream verdict, not the loop gate); the edge is left as it
// is. `scans` must outlive the decision; cfg is copied.
eval::LoopDecision streamVerdictDecision(const std::vector<eval::TrainingScan>& scans,
                                         const online::IntrospectorConfig& cfg);

}  // namespace ros_eval
}  // namespace coral_introspection
