// A second registration from several starts, for a loop candidate the verdict accepts at its
// pose (the loop gate's `restarts`, verdict.hpp; doc/loop_closure.md). The back end's ICP
// converged at the candidate's pose, a local optimum. Registered again from starts around it,
// a right candidate comes back to it or ends at worse poses, while one registered a metre off
// along repeated structure (Intel's cubicle rows, ACES's corridors) finds the revisit's true
// pose, which the loop verdict accepts and which fits clearly better (lower Q, Eq. 5). CorAl's
// Q alone cannot find that pose: its minimum at a true pose is a few centimetres wide,
// narrower than any probe step that keeps a search affordable, while a registration converges
// into it. ROS-free, no exceptions.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "coral_introspection/coral/coral_pair.hpp"
#include "coral_introspection/coral/registration.hpp"
#include "coral_introspection/coral/tolerance.hpp"

namespace coral_introspection {
namespace coral {

struct RestartConfig {
  // Starts: the candidate's pose moved in b's x-y plane by each radius [tolerances, i.e.
  // multiples of tolerance/translation] in `directions` evenly spaced directions.
  std::vector<double> radii = {2.5, 4.0};
  int directions = 8;
  // A better alignment elsewhere: a registration result at least min_distance tolerances
  // (toleranceSize) from the candidate's pose that the loop verdict accepts, whose Q is
  // below the candidate's by at least (1 - max_q_ratio) |Q|, and whose overlap is at least
  // min_overlap_ratio of the candidate's. Without the last condition, a pose that fits only
  // part of the scans (one wall of a corridor) has a lower Q than the true pose of a revisit:
  // Q is a mean over the overlapping points.
  double min_distance = 2.0;
  double max_q_ratio = 0.8;
  double min_overlap_ratio = 0.9;
  // Coarse to fine, for dense 3D scans: each start is registered first with at most
  // coarse_points of b's points until an update moves less than coarse_min_step [m and rad]
  // or the pose comes within coarse_back_within tolerances of the candidate's (heading back
  // there; for starts farther out than that). One that ends within min_distance of the
  // candidate's pose ends the start; any other is registered again with all points
  // (SurfaceTarget::kMaxSourcePoints) from where it ended, ended the same way once it comes
  // within coarse_back_within tolerances of the candidate's pose. The nearest-point search is most
  // of a registration's cost, and the starts of a right candidate come back to it (all 16 on
  // the 64-beam timing pair, doc/loop_closure.md). Only when b has more points than
  // coarse_points (2D scans of up to 361 beams are registered once, as before); 0 = off.
  std::size_t coarse_points = 500;
  double coarse_min_step = 1e-3;
  double coarse_back_within = 1.0;  // [tolerances] in (0, min_distance]
  // [tolerances] in [0, coarse_back_within]: a start whose coarse registration comes within
  // this of where an earlier start's ended is stopped there and counted with that one
  // (RestartResult::merged), not registered again: the starts that end away mostly end at one pose
  // (the revisit, or a pose along repeated structure), and each full registration of a dense scan
  // costs 0.03-0.05 s (doc/loop_closure.md "The cost of a rejection"). 0 = register each.
  double coarse_same_within = 0.25;
  RegistrationConfig registration;
  std::string validate() const;        // empty when valid; registration's messages "registration: "
  std::string validateStarts() const;  // the same without registration's
};

struct RestartResult {
  bool run = false;               // the check ran (a valid candidate the loop verdict accepted)
  bool better_elsewhere = false;  // a better alignment was found: the candidate is rejected
  Eigen::Isometry3d T_a_b = Eigen::Isometry3d::Identity();  // the best one found, if any
  double distance = 0.0;       // its distance from the candidate's pose [tolerances]
  double q = 0.0;              // its Q [nats]
  double q_candidate = 0.0;    // the candidate's Q [nats]
  int starts = 0, usable = 0;  // registrations run and usable (RegistrationResult::usable)
  int merged = 0;  // starts counted with an earlier one (RestartConfig::coarse_same_within)
  // Full registrations ended once back within coarse_back_within of the candidate's pose.
  int returned = 0;
  // Usable starts that ended within min_distance of the candidate's pose (back at it).
  int back = 0;
};

// The loop verdict at one pose, as the check needs it.
struct JudgedPose {
  bool accepted = false;  // the loop verdict accepts the pose
  double quality = 0.0;   // Q there (Eq. 5) [nats]
  double overlap = 0.0;   // CorAl's overlap fraction there [-]
};
using PoseJudge = std::function<JudgedPose(const Eigen::Isometry3d& T_a_b)>;

// For the candidate T_a_b of the prepared pair (a in its frame, b in its own), judged
// `candidate` at its pose: registers pair.points(1) onto pair.points(0) from every start
// (SurfaceTarget, cfg.registration) and judges each usable result at least
// cfg.min_distance tolerances away with `judge` (only those whose Q and overlap, one CorAl
// evaluation, could make them better). `target`, when given, is pair.points(0) prepared with
// pair.config() and cfg.registration (shared with registeredNearby); else one is built.
// Preconditions: cfg.validate() and tolerance.validate() are empty. Never throws.
RestartResult betterAlignmentElsewhere(const CoralPair& pair, const Eigen::Isometry3d& T_a_b,
                                       const JudgedPose& candidate,
                                       const ToleranceConfig& tolerance, const RestartConfig& cfg,
                                       const PoseJudge& judge,
                                       const SurfaceTarget* target = nullptr);

// A loop candidate the verdict rejects at its pose, registered once from that pose (the loop
// gate's max_registered_offset, verdict.hpp). A back end's ICP that stopped 0.15-0.3 m short
// of a true revisit (point-to-point ICP on 2D scans, doc/loop_closure.md) is within the
// tolerance, yet rejected at its pose: the relative check finds a lower Q one tolerance on and
// the classifier, trained on exact poses, a low p. The verdict's promise is about the size of
// the error, and a registration from the pose measures it: it converges into the nearby
// minimum, a few centimetres wide, that Q's probes step over. When that pose is within
// max_size (< 1) tolerances and the loop verdict accepts it there, the given pose is within
// the tolerance of an alignment the verdict accepts.
struct NearbyAlignment {
  bool run = false;       // registered (the verdict rejected a valid candidate at its pose)
  bool usable = false;    // the registration gave a pose (RegistrationResult::usable)
  bool accepted = false;  // usable, within max_size tolerances, and `accepts` said yes there
  bool screened = false;  // ended by the screen (below) a tolerance away, where T_a_b is
  Eigen::Isometry3d T_a_b = Eigen::Isometry3d::Identity();  // the registered pose
  double size = 0.0;  // its distance from the candidate's pose [tolerances] (toleranceSize)
};

// Registers pair.points(1) onto pair.points(0) from T_a_b (SurfaceTarget,
// restart.registration) and, when the result is usable and within max_size tolerances of
// T_a_b, asks `accepts` about it (called at most once). A dense scan (more points than
// restart.coarse_points) with max_size < 1 is screened: registered first by the restart
// check's coarse phase (coarse_points, coarse_min_step), then fully from T_a_b, each stopped
// once the pose is a tolerance away (it has left the tolerance: `screened`, not accepted, not
// asked). A registration that stays within a tolerance ends as without the screen. `target`:
// as betterAlignmentElsewhere's. Preconditions: restart.validate() and tolerance.validate()
// are empty. Never throws.
NearbyAlignment registeredNearby(const CoralPair& pair, const Eigen::Isometry3d& T_a_b,
                                 const ToleranceConfig& tolerance, const RestartConfig& restart,
                                 double max_size,
                                 const std::function<bool(const Eigen::Isometry3d&)>& accepts,
                                 const SurfaceTarget* target = nullptr);

}  // namespace coral
}  // namespace coral_introspection
