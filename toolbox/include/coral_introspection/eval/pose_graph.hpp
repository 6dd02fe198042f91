// A small keyframe pose-graph optimiser (Ceres) for the evaluation: odometry and loop-closure
// edges are relative-pose factors between keyframe poses T_world_k, so a drifted odometry
// chain closed by loop edges can be corrected and scored against ground truth (ATE) before
// and after, and written as TUM / KITTI trajectories for external tools (evo). Planar
// (x, y, yaw) or full SE(3). ROS-free; nothing here throws.
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/coral/tolerance.hpp"
#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace eval {

// Relative-pose measurement T_from_to between poses `from` and `to` (indices into the pose
// list). Its residual r = Log(T_from_to^-1 T_world_from^-1 T_world_to) = (translation [m],
// rotation vector [rad]) is whitened by the sigmas.
struct PoseGraphEdge {
  int from = 0, to = 0;
  Eigen::Isometry3d T_from_to = Eigen::Isometry3d::Identity();
  double sigma_translation = 0.1;  // [m] per axis, > 0
  double sigma_rotation = 0.01;    // [rad] per axis, > 0
  bool loop = false;               // loop-closure edge (the robust loss applies to these only)
};

// Sigmas of a registered loop edge [m], [rad]: about a tenth of the tolerance (the relation
// graph of a CARMEN log, coral_loop_eval's loop edges).
constexpr double kLoopEdgeSigmaT = 0.05, kLoopEdgeSigmaR = 0.01;

struct PoseGraphConfig {
  // 2: planar, each pose optimises x, y, yaw (z, roll, pitch held at their initial values;
  // edges use only the planar part of T_from_to); 3: full SE(3).
  int dimension = 3;
  int max_iterations = 100;  // Levenberg-Marquardt iterations, >= 1
  // Huber scale on loop edges in whitened units (sigmas), so a wrong loop closure pulls with
  // bounded force; 0 = plain least squares. Odometry edges are never robustified.
  double huber_loss = 0.0;
  // Continuation from a badly drifted start: solve first with the loop edges' sigmas scaled
  // by each factor in turn (e.g. {100, 30, 10, 3}), each stage starting where the last ended,
  // then with the true sigmas. Loop edges that pull the chain far from its start (metres of
  // odometry drift, tens of degrees of yaw) otherwise leave LM in a local minimum: on the
  // Intel log the oracle graph's relation error falls from 0.074 m / 4.2 deg to the
  // reference's own 0.036 m / 1.8 deg (doc/loop_closure.md). Empty = one solve. Factors > 1.
  std::vector<double> loop_sigma_schedule;
  // Planar only (dimension 2): solve (continuation included) from the given poses and again
  // from planarLinearStart of the edges, and keep the solution of lower final cost. From the
  // raw odometry the continuation leaves the Intel log's graphs in a folded local minimum of
  // 2.4-2.8x the cost; from the linear start, which a wrong loop edge pulls as hard as a right
  // one, graphs holding false edges can end worse than from the odometry (ACES; both:
  // doc/loop_closure.md "Intel's graphs were folded"). result: the kept solve's, iterations of
  // both.
  bool try_linear_start = false;
  std::string validate() const;  // empty when valid
};

// Huber 1.0 on loop edges (hdl_graph_slam's) and the continuation {100, 30, 10, 3}: the graphs
// coral_loop_eval optimises per gate and the relation graph of a CARMEN log (log_nodes.hpp).
PoseGraphConfig robustContinuationConfig(int dimension);

struct PoseGraphResult {
  bool converged = false;  // Ceres reached a convergence tolerance (not the iteration cap)
  int iterations = 0;      // LM steps taken (successful + unsuccessful), every stage
  double initial_cost = 0.0, final_cost = 0.0;  // Ceres cost: 0.5 * sum of rho(|r|^2)
  std::string error;                            // set when optimizePoseGraph returns false
};

// Optimises the poses T_world_k in place; the first pose is held fixed (gauge). True when
// Ceres returned a usable solution (also when it stopped at max_iterations: see converged).
// False with result->error (poses untouched) on an invalid config, no poses, an edge index
// out of range or from == to, or a non-positive / non-finite sigma.
bool optimizePoseGraph(const std::vector<PoseGraphEdge>& edges, const PoseGraphConfig& cfg,
                       coral::Isometries* poses, PoseGraphResult* result);

// A consistency check a back end may run after its loop gate: solve, find the loop edge the
// optimum explains worst, and when its residual exceeds `max_residual` tolerances
// (coral::toleranceSize of T_from_to^-1 T_world_from^-1 T_world_to) remove it and solve again
// from that optimum (without the continuation), at most `max_removals` times. One wrong edge
// among many right ones bends the graph near it and is left with the largest residual; when
// wrong edges are many (an ICP-fitness gate), they bend it together and max_removals ends the
// search first, with *consistent false. It only works where the odometry and the right edges
// agree to within max_residual: on the Intel log's raw odometry the optimum leaves right
// edges farther off than that, and the graph folds without them (doc/loop_closure.md).
// *removed: the removed edges' indices into `edges`, worst first; *consistent: every remaining
// loop edge within max_residual; *poses: the last solve. False with result->error (poses
// untouched) on an invalid pruning or tolerance config, or when a solve fails
// (optimizePoseGraph's reasons).
struct LoopPruning {
  // [tolerances] > 0: well past the 2 tolerances from which a loop candidate is false
  // (eval/loop_candidates.hpp), so that a right edge the optimum leaves strained is kept.
  double max_residual = 3.0;
  int max_removals = 25;         // >= 0; solves: at most max_removals + 1
  std::string validate() const;  // empty when valid
};
bool optimizePrunedPoseGraph(std::vector<PoseGraphEdge> edges, const PoseGraphConfig& cfg,
                             const coral::ToleranceConfig& tolerance, const LoopPruning& pruning,
                             coral::Isometries* poses, std::vector<int>* removed, bool* consistent,
                             PoseGraphResult* result);

// A start for a planar graph that does not depend on the given poses, so the odometry's drift
// cannot trap the solve that follows in a local minimum: the orientations by the chordal
// relaxation (each node's (cos, sin) free, every edge's rotation a linear constraint between
// them; least squares, then normalised: no angle is unwrapped, so no multiple of 2 pi is
// guessed), then the positions by linear least squares with the orientations fixed (LAGO's
// second step). Carlone et al., "Initialization techniques for 3D SLAM", ICRA 2015 (chordal);
// "A fast and accurate approximation for planar pose graph optimization", IJRR 2014 (LAGO).
// Not robust: a wrong loop edge pulls the start as hard as a right one (the robust solve from
// it then weighs it). Node 0, and z, roll and pitch of every pose, are kept; a node no edge
// reaches keeps its pose. False with *error on no poses, an edge out of range, from == to or
// without sigmas, or a failed solve.
bool planarLinearStart(const std::vector<PoseGraphEdge>& edges, coral::Isometries* poses,
                       std::string* error);

// Edges k -> k+1 with the relative poses of consecutive odometry poses (loop = false).
std::vector<PoseGraphEdge> odometryEdges(const coral::Isometries& odom_poses,
                                         double sigma_translation, double sigma_rotation);

// Absolute trajectory error [m]: RMSE of the position differences after the best rigid
// alignment (no scale) of estimate onto reference, pose k with pose k. dimension 2: only x,
// y and yaw are aligned and the error is horizontal; otherwise SE(3) Umeyama on the positions
// (trajectoryErrors of trajectory_metrics.hpp). NaN when the sizes differ or are 0.
double absoluteTrajectoryError(const coral::Isometries& estimate,
                               const coral::Isometries& reference, int dimension);

// TUM file ("stamp tx ty tz qx qy qz qw" per line; writeTum of trajectory_metrics.hpp).
// False with *error when the sizes differ or the file cannot be written.
bool writeTumTrajectory(const std::string& path, const std::vector<double>& stamps,
                        const coral::Isometries& poses, std::string* error);

// KITTI pose file (3x4 row-major [R | t] per line), the layout readKittiPoses (cloud_io.hpp)
// reads. False with *error when the file cannot be written.
bool writeKittiPoses(const std::string& path, const coral::Isometries& poses, std::string* error);

}  // namespace eval
}  // namespace coral_introspection
