// Loop-closure candidates as a SLAM back end meets them, on real sequences with reference
// poses: pairs of scans far apart in time, proposed (a) within a radius of each other, as
// LIO-SAM and hdl_graph_slam propose them, registered from the odometry's relative pose, and
// (b) as look-alike places (any two scans, far apart in the reference) registered from
// several headings, as a place recognizer's false match followed by ICP hands them over.
// Registration is PCL's (GICP, NDT or point-to-point ICP in 3D; point-to-point ICP with a
// planar estimator or point-to-line ICP in 2D).
// Every registered candidate is labelled by its error against the reference relative pose:
// true when within the tolerance, false when off by `false_multiple` tolerances or more
// (those are "wrong but locally optimal": ICP converged there); in between it is left out.
// Used by coral_loop_eval (doc/loop_closure.md) and the loop-closure tests.
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/coral/tolerance.hpp"
#include "coral_introspection/eval/training_set.hpp"

namespace coral_introspection {
namespace eval {

struct LoopCandidateConfig {
  int dimension = 3;  // 2: planar registration (x, y, yaw), 3: 6 DoF
  // 3D: "gicp" (PCL GeneralizedIterativeClosestPoint) or "ndt" (PCL
  // NormalDistributionsTransform, ndt_resolution cells), the two hdl_graph_slam offers, or
  // "icp" (PCL point-to-point ICP, 6 DoF, as LIO-SAM registers its loop candidates; with
  // LIO-SAM's 30 m correspondences and 100 iterations in place of max_correspondence and
  // max_iterations).
  // 2D: "icp" (PCL point-to-point ICP, planar estimator) or "point_to_line" (PCL point-to-plane
  // ICP with 2D line normals, x, y, yaw: PL-ICP, as ROS's laser_scan_matcher registers scans).
  std::string registration = "gicp";
  double ndt_resolution = 1.0;          // [m] NDT cell size (hdl_graph_slam's default)
  int min_index_gap = 50;               // [scans] a loop joins scans at least this far apart
  double radius = 3.0;                  // [m] (a): reference distance of a revisit
  double lookalike_min_distance = 8.0;  // [m] (b): reference distance of different places
  int max_radius_candidates = 60;       // (a) kept, spread evenly over the qualifying pairs
  int max_lookalike_pairs = 40;         // (b) scan pairs registered from each heading
  std::vector<double> headings_deg = {0, 90, 180, 270};  // (b) initial yaw of b in a
  double max_correspondence = 1.5;                       // [m] registration's correspondence gate
  int max_iterations = 50;
  double fitness_range = 1.0;   // [m] PCL getFitnessScore max range (mean squared NN distance)
  double false_multiple = 2.0;  // off by >= this many tolerances: a false candidate
  // A back end's view: revisits proposed within `radius` of the odometry poses (LIO-SAM,
  // hdl_graph_slam) instead of the reference; candidates between the tolerance and
  // false_multiple tolerances kept (as false: off by the tolerance or more).
  bool propose_by_odometry = false;
  bool keep_ambiguous = false;
  // Revisits registered from the reference relative pose moved by this much along x and yaw
  // (a front end whose drift was already corrected) instead of from the odometry; < 0 = from
  // the odometry. For logs whose raw odometry drifts by metres (CARMEN).
  double init_offset = -1.0;         // [m]
  double init_offset_deg = 10.0;     // [deg] with init_offset >= 0
  coral::ToleranceConfig tolerance;  // the preset's: true = within it
  std::string validate() const;      // empty when valid
};

struct LoopCandidate {
  int a = 0, b = 0;           // scan indices (a earlier)
  std::string source;         // "radius" or "lookalike" (or "relation": a benchmark relation as is)
  double init_yaw_deg = 0.0;  // lookalike: initial heading
  Eigen::Isometry3d T_a_b = Eigen::Isometry3d::Identity();  // the registration's result
  bool converged = false;
  double fitness = 0.0;            // PCL fitness score [m^2] (LIO-SAM accepts <= 0.3)
  double error_translation = 0.0;  // [m] against the reference relative pose
  double error_rotation_deg = 0.0;
  bool is_true = false;  // within the tolerance of the reference
  // The reference relative pose (b in a's frame) it is labelled against: what a pose the
  // verdict offers for it in place of T_a_b (a refined pose) is measured against.
  Eigen::Isometry3d T_ref = Eigen::Isometry3d::Identity();
};

// The candidate settings of the evaluation (doc/loop_closure.md, coral_loop_eval,
// test_loop_closure): keyframe sequences (dimension 3) propose revisits within 3 m of the
// odometry poses, at least 50 keyframes apart, registered from the odometry; CARMEN logs
// (dimension 2), whose raw odometry drifts by metres, propose them where the reference says
// (a working place recognizer), at least 30 corrected scans apart (up to 300 revisits and 60
// look-alike pairs), registered by point-to-point ICP from the reference moved by 0.5 m and
// 10 deg. Tolerance: the preset's.
LoopCandidateConfig evaluationCandidates(int dimension, const coral::ToleranceConfig& tolerance);

// PCL's fitness score as a CSV cell: "inf" where PCL reports the largest double (no
// correspondence within fitness_range, or a scan too small to register), the number otherwise.
std::string fitnessCell(double fitness);

// Registers b onto a from T_init (b's points into a's frame) and fills T_a_b, converged,
// fitness. Scans in their own sensor frames. A scan of fewer than kMinRegistrationPoints points
// is not registered: T_a_b = T_init, not converged, fitness the largest double.
constexpr std::size_t kMinRegistrationPoints = 20;
void registerPair(const coral::Points& a, const coral::Points& b, const Eigen::Isometry3d& T_init,
                  const LoopCandidateConfig& cfg, LoopCandidate* c);

// Candidates (a) and (b) of a sequence with reference poses T_world_scan (the reference
// also decides true / false) and odometry poses (the initial guess of (a)); candidates in
// the ambiguous band between the tolerance and false_multiple tolerances are dropped.
// Deterministic. False with *error on an invalid config or mismatched sizes.
bool buildLoopCandidates(const std::vector<TrainingScan>& scans,
                         const coral::Isometries& T_world_ref,
                         const coral::Isometries& T_world_odom, const LoopCandidateConfig& cfg,
                         std::vector<LoopCandidate>* out, std::string* error);

// Candidates as a back end without reference poses proposes them (coral_pose_graph): (a)
// revisits within cfg.radius of each other in the odometry T_world_odom, registered from its
// relative pose (as LIO-SAM and hdl_graph_slam do), and (b) pairs at least
// cfg.lookalike_min_distance apart in the odometry registered from cfg.headings_deg, what a
// place recognizer's matches hand over (none when cfg.max_lookalike_pairs is 0). Unlabelled:
// is_true false, no error, T_ref identity. Deterministic. False with *error on an invalid
// config or mismatched sizes.
bool proposeLoopCandidates(const std::vector<TrainingScan>& scans,
                           const coral::Isometries& T_world_odom, const LoopCandidateConfig& cfg,
                           std::vector<LoopCandidate>* out, std::string* error);

// Revisits with exact labels (CARMEN logs): every known relative pose of `pairs` (the
// benchmark relations joining scans far apart in time) registered again from that pose
// moved by cfg.init_offset [m] along +x, -x, +y, -y with +-cfg.init_offset_deg of yaw (a
// back end's drifted guess), so that registration ends on the revisit or on a wrong local
// optimum near it; each result is labelled against the relation itself, not against a
// trajectory estimate (the logs' corrected poses disagree with the relations by decimetres
// in places, more than the tolerance's share). Source "relation_icp"; a, b index `scans`.
// At most cfg.max_radius_candidates pairs are used, spread evenly; the ambiguous band is
// dropped as in buildLoopCandidates. False with *error on an invalid config.
bool relationRegistrations(const std::vector<TrainingScan>& scans,
                           const std::vector<ScanPair>& pairs, const LoopCandidateConfig& cfg,
                           std::vector<LoopCandidate>* out, std::string* error);

// An error of t [m] and r_deg [deg] against the reference is within the tolerance: the label
// of a true loop candidate (and of a pose offered in place of its own).
bool withinTolerance(double t, double r_deg, const coral::ToleranceConfig& tol);

// Error of T_a_b against the reference T_ref: translation [m], rotation [deg].
void relativeError(const Eigen::Isometry3d& T_a_b, const Eigen::Isometry3d& T_ref, double* t,
                   double* r_deg);

}  // namespace eval
}  // namespace coral_introspection
