// Loop closure as a running SLAM back end does it, for odometry that drifts by metres between
// revisits (a CARMEN log's wheel odometry: Intel 23 m ATE, 39 deg mean relation error), where a
// radius around the raw odometry (proposeLoopCandidates) finds few of the revisits. Keyframes
// arrive in order. For each, the nearest earlier keyframe at least cfg.min_index_gap back that
// lies within cfg.radius of it in the *current estimate* (LIO-SAM's loop thread searches its
// optimised key poses, not the odometry) is registered from the estimate's relative pose
// (registerPair) and handed to the back end's decision; an accepted edge enters the graph,
// which is optimised over the keyframes so far at once (unless the estimate already agrees with
// the edge within half a tolerance), so that the next proposals start from the corrected
// estimate. ROS-free; nothing here throws.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "coral_introspection/eval/loop_candidates.hpp"
#include "coral_introspection/eval/odometry_calibration.hpp"
#include "coral_introspection/eval/pose_graph.hpp"

namespace coral_introspection {
namespace eval {

// The back end's decision on a registered candidate: true to add it as a loop edge, with the
// measurement in *T_edge (set to the candidate's T_a_b before the call).
using LoopDecision = std::function<bool(const LoopCandidate&, Eigen::Isometry3d* T_edge)>;

// A back end's check of a loop edge before it enters the graph (e.g. its agreement with the
// odometry, eval::odometryInconsistentLoops): true to add it. seed: the index into `seeds` of a
// seed, -1 for a candidate the decision accepted.
using EdgeCheck = std::function<bool(const PoseGraphEdge&, int seed)>;

struct IncrementalLoops {
  std::vector<LoopCandidate> proposed;    // in arrival order (a earlier, b the new keyframe)
  std::vector<PoseGraphEdge> loop_edges;  // the accepted ones (with the seeds given) admitted
  int refused = 0;                        // accepted edges and seeds the check kept out
  int solves = 0;                         // graph optimisations run
  PoseGraphResult last;                   // the final solve, over every keyframe and edge
};

// scans, T_world_odom: the keyframes and their odometry. cfg: radius, min_index_gap,
// registration (max_radius_candidates and the look-alike fields are not used). odometry:
// the odometry edges (k -> k+1). seeds: loop edges known before the run (e.g. decided look-alike
// registrations), added once both ends have arrived. *poses: the final estimate, optimised once
// more over every edge. admit (optional): asked about every accepted edge and every seed before
// it enters the graph. False with *error on an invalid config, mismatched sizes or a failed
// optimisation.
bool closeLoopsIncrementally(const std::vector<TrainingScan>& scans,
                             const coral::Isometries& T_world_odom, const LoopCandidateConfig& cfg,
                             const std::vector<PoseGraphEdge>& odometry,
                             const std::vector<PoseGraphEdge>& seeds, const PoseGraphConfig& graph,
                             const LoopDecision& decide, coral::Isometries* poses,
                             IncrementalLoops* out, std::string* error,
                             const EdgeCheck& admit = {});

// A scan-matching front end's measurements of wheel odometry's steps: keyframe k registered onto
// k - 1 (registerPair, cfg's registration) from the odometry's relative pose; element k - 1 holds
// the registration when `accept` takes it (the stream verdict: the package's use for odometry),
// else nothing. Sizes must match (the result is empty otherwise).
std::vector<std::optional<Eigen::Isometry3d>> scanMatchedSteps(
    const std::vector<TrainingScan>& scans, const coral::Isometries& T_world_odom,
    const LoopCandidateConfig& cfg, const LoopDecision& accept);

// The front end itself (what a 2D SLAM's front end does before its back end sees a keyframe):
// the steps scanMatchedSteps measured replace the odometry's, the others stay. Returns the
// chained poses (the first one the odometry's); *accepted counts the steps replaced. Sizes must
// match (the result is empty otherwise).
coral::Isometries scanMatchedOdometry(const std::vector<TrainingScan>& scans,
                                      const coral::Isometries& T_world_odom,
                                      const LoopCandidateConfig& cfg, const LoopDecision& accept,
                                      int* accepted);

// The other front end: the wheel odometry kept, its yaw calibrated (fitOdometryYaw, at least 20
// measured steps) on the steps scanMatchedSteps measured and corrected on every step
// (correctOdometryYaw), as a back end calibrates its odometry before trusting its covariance.
// False with *error when the fit refuses the steps (too few, or they do not tell the yaw gain
// from the bias per metre).
bool calibratedOdometry(const std::vector<TrainingScan>& scans,
                        const coral::Isometries& T_world_odom, const LoopCandidateConfig& cfg,
                        const LoopDecision& accept, coral::Isometries* calibrated,
                        OdometryYawModel* model, std::string* error);

}  // namespace eval
}  // namespace coral_introspection
