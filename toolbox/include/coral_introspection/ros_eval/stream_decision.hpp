// The preset's stream verdict as an eval::LoopDecision: what the package says of an odometry
// step, the decision the scan-matching front ends keep a registered step by
// (eval::scanMatchedSteps: coral_pose_graph --front_end, coral_loop_eval --calibrate_odometry).
#pragma once

#include <vector>

#include "coral_introspection/eval/incremental_loops.hpp"
#include "coral_introspection/online/introspector_config.hpp"

namespace coral_introspection {
namespace ros_eval {

// The verdict rejected its pose because the registration from it reached a lower minimum of Q
// (the coarse probe's words "a lower minimum of Q nearby"; T_a_b * v.coarse.lowest.delta), and
// the pose is not a corridor's (the gate's constraint term, when measured, at its bound or
// above). Method kGated only.
bool lowerMinimumNearby(const coral::AlignmentVerdict& v, const coral::VerdictConfig& cfg);

// Accepts candidate c when online::judgePair on scans[c.a], scans[c.b] at c.T_a_b gives a valid
// verdict that says aligned (cfg's stream verdict, not the loop gate); the edge is left as it
// is. When the verdict rejects c because its coarse probe's registration reached a lower Q
// (lowerMinimumNearby), the pose that registration reached is judged too, and when aligned
// there c is accepted with *T_edge set to it (a front end's second registration, paid only by
// rejected steps).
// `scans` must outlive the decision; cfg is copied.
eval::LoopDecision streamVerdictDecision(const std::vector<eval::TrainingScan>& scans,
                                         const online::IntrospectorConfig& cfg);

}  // namespace ros_eval
}  // namespace coral_introspection
