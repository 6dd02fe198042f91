// Pairwise consistency of loop edges (PCM, Mangelson et al., ICRA 2018), the check a back end
// may run on the loop closures its gate accepted, before it adds them: two loop edges are
// consistent when the cycle they close with the odometry between their ends returns to its
// start within the uncertainty of the four pieces (Mahalanobis distance under a chi-square
// bound); the largest set of mutually consistent loop edges is kept, the rest rejected. Unlike
// a residual bound on the optimum (optimizePrunedPoseGraph), a long stretch of drifting
// odometry makes the bound wide, not the right edges wrong. ROS-free; nothing here throws.
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/eval/pose_graph.hpp"

namespace coral_introspection {
namespace eval {

struct PairwiseConsistencyConfig {
  // Probability of the chi-square bound on the cycle's squared Mahalanobis distance, with 3
  // degrees of freedom (dimension 2: x, y, yaw) or 6 (dimension 3). In (0, 1).
  double probability = 0.99;
  int dimension = 3;  // 2 or 3, as PoseGraphConfig::dimension
  // The largest consistent set is found greedily (exact maximum clique is NP-hard): from each
  // of the max_starts loop edges with the most consistent partners, add the candidate with the
  // most consistent partners among the remaining candidates until none is left; the largest
  // set wins. >= 1.
  int max_starts = 32;
  std::string validate() const;  // empty when valid
};

// The loop edges of `edges` (loop = true) that are not in the largest mutually consistent set:
// their indices into `edges`, ascending, in *rejected. The non-loop edges must be the odometry
// chain 0 -> 1 -> ... -> n-1 in order (eval::odometryEdges): the cycles use it and its sigmas
// (first-order propagation along the chain). False with *error on an invalid config or a graph of
// another shape.
bool pairwiseInconsistentLoops(const std::vector<PoseGraphEdge>& edges,
                               const PairwiseConsistencyConfig& cfg, std::vector<int>* rejected,
                               std::string* error);

// The loop edges of `edges` each of which, alone, disagrees with the odometry between its ends
// beyond the chi-square bound of cfg.probability: the cycle loop edge + odometry back to its
// start, first order as above (PCM's odometry check, which Kimera-RPGO runs before the pairwise
// one). It needs no other loop edge, so it also judges the first loop closure of a run, where
// a largest consistent set of one edge accepts anything. Same shape requirements and errors as
// pairwiseInconsistentLoops; *rejected ascending.
bool odometryInconsistentLoops(const std::vector<PoseGraphEdge>& edges,
                               const PairwiseConsistencyConfig& cfg, std::vector<int>* rejected,
                               std::string* error);

// The loop edges a back end leaves out (`--pcm` of coral_loop_eval and coral_pose_graph): those
// odometryInconsistentLoops rejects, then those of the rest outside the largest pairwise
// consistent set. *rejected: both, indices into `edges`, ascending; *by_odometry (optional):
// how many the first part rejected. Errors as pairwiseInconsistentLoops.
bool inconsistentLoopEdges(const std::vector<PoseGraphEdge>& edges,
                           const PairwiseConsistencyConfig& cfg, std::vector<int>* rejected,
                           int* by_odometry, std::string* error);

// `edges` without those at the (ascending) indices `rejected`: the graph a back end optimises.
std::vector<PoseGraphEdge> keptEdges(const std::vector<PoseGraphEdge>& edges,
                                     const std::vector<int>& rejected);

}  // namespace eval
}  // namespace coral_introspection
