// The alignment verdict of one scan pair at the user's tolerance: CorAl (Eq. 5), then the
// trained classifier (Eq. 9-10), the training-free relative check (relative_check.hpp) or
// both. "Misaligned" means off by at least the tolerance. One function for every caller
// (online introspection, check_alignment, the tests on real pairs).
#pragma once

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "coral_introspection/coral/classifier.hpp"
#include "coral_introspection/coral/coarse_probe.hpp"
#include "coral_introspection/coral/constraint.hpp"
#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/coral/coral_pair.hpp"
#include "coral_introspection/coral/free_space.hpp"
#include "coral_introspection/coral/refinement.hpp"
#include "coral_introspection/coral/relative_check.hpp"
#include "coral_introspection/coral/restart_check.hpp"
#include "coral_introspection/coral/tolerance.hpp"

namespace coral_introspection {
namespace coral {

enum class VerdictMethod {
  kClassifier,  // logistic regression on (H_joint, H_sep): 1 CorAl evaluation
  kRelative,    // Q against Q one tolerance away: 1 + 2 x axes evaluations, no training
  kBoth,        // aligned only when both say aligned (same cost as kRelative)
  kGated,       // relative check, and the absolute gate below passed (same cost as kRelative)
};
const char* verdictMethodName(VerdictMethod m);  // "classifier", "relative", "both", "gated"
bool parseVerdictMethod(const std::string& name, VerdictMethod* m);

// The absolute terms of the gated verdict. The relative check compares Q only with poses
// one tolerance away, and past the CorAl radius Q falls again: a pose off by several radii,
// or a false loop closure that ICP converged on (a local minimum of Q), passes it. How
// aligned pairs of the sensor look in absolute terms does not depend on where the nearest
// minimum of Q lies: the classifier's p (Eq. 9, on H_joint and H_sep) of such poses is
// orders of magnitude below that of aligned pairs, and little of the scans overlaps. The
// gate is loose on purpose (the relative check judges errors of one tolerance): it only
// has to reject what lies far beyond the tolerance (doc/verdict_every_error.md).
struct GateConfig {
  double min_probability = 0.0;  // [-] classifier p at the pose must reach this; 0 = off
  double min_overlap = 0.0;      // [-] CorAl's overlap fraction at the pose; 0 = off
  // [-] the free-space conflict at the pose (free_space.hpp: fraction of one scan's points
  // lying where the other saw through) must not exceed this; 1 = off. Two look-alike places
  // (corridors, repeated rooms) that registration fitted together satisfy Q locally; their
  // corridor ends, doors and side openings fall into each other's free space.
  double max_free_space = 1.0;
  // [tolerances^2] how firmly the shared structure pins the pose (constraint.hpp: in effect,
  // how many shared surface points move by a full tolerance under the weakest one-tolerance
  // error) must reach this; 0 = off. Two scans that share only a corridor's walls or a short
  // piece of wall are consistent at many poses: a registration that stopped at the wrong one
  // passes CorAl, the classifier and the free-space term alike.
  double min_constraint = 0.0;
  // [deg] 2D: the beam spacing min_constraint is stated for; the constraint of a scan of
  // another spacing counts its points by their share (constraint.hpp beamSpacingShare), so
  // a denser scanner does not pass the bound on half the geometry. 0 = points as they are.
  double constraint_beam_step_deg = 0.0;
  // [nats] Q at the pose (Eq. 5: H_joint - H_sep) must not exceed this; infinity = off.
  // Registration leaves a look-alike place at a local minimum of Q, where the relative check
  // says aligned, but that minimum can lie high: the two places' surfaces lie near each
  // other without coinciding. CorAl's own absolute test (a threshold on Q) as a loose bound
  // beside the classifier's (which weighs H_joint and H_sep apart).
  double max_quality = std::numeric_limits<double>::infinity();
  // How many of x, y and yaw the relative check may report flat at the pose
  // (relative_check.hpp: Q changes along them by less than flat_ratio of the most sensitive
  // axis; horizontalFlatAxes); -1 = off. Two look-alike places that registration fitted
  // together often match along one direction only (a 3D scan turned by 60-130 deg onto another
  // place: Q rises steeply along one or two axes and hardly along x, y or yaw), so CorAl pins
  // nothing there (doc/loop_closure.md, "Ten times the look-alike places"). z, roll and pitch
  // are not counted: the ground pins them, and a narrow-FOV lidar's roll is weak at true poses
  // too ("Flat axes counted over x, y and yaw"). In [-1, 2] (3 would never reject).
  int max_flat_axes = -1;
  // [tolerances] coarse probe (coarse_probe.hpp): Q is evaluated 2, 4, 6, ... (every even
  // number up to this) tolerances away along each axis, both ways, and a quarter and half turn
  // about z away; the pose is rejected when one of them has Q lower by more than coarse_margin:
  // the pose sits on a local minimum of Q past the CorAl radius that the relative check's
  // one-tolerance steps cannot leave (most 2D errors of 2 tolerances or more that passed the
  // other terms, doc/verdict_every_error.md). Steps two tolerances apart leave every error along
  // an axis up to the largest step within one tolerance of a step, the size the relative check
  // resolves (powers of two left 6 and 10 tolerances two away from any step). 0 = off, else in
  // [2, 16]. Costs 2 x axes x (coarse_max_multiple / 2) + 3 probe evaluations (probe queries)
  // per verdict.
  int coarse_max_multiple = 0;
  // The coarse probe also registers b onto a once from the pose (VerdictConfig::restart's
  // registration) and probes the result when it lies a tolerance or more away: errors between
  // the steps' sizes land off the narrow minimum of Q at the truth, a registration into it.
  bool coarse_registration = false;
  // [tolerances] the registered pose is probed when it lies at least this far from the pose
  // (toleranceSize). A registration measures an error to about +-0.15 tolerances (Livox pairs
  // moved by one tolerance come back 0.8-1.1 away, doc/verdict_every_error.md "Probed from 0.8
  // tolerances"): with 1, half of the errors of exactly one tolerance are not probed. Below 1
  // catches them, at the price of probing poses a little inside the tolerance too (those are
  // rejected only where Q is lower there by coarse_margin). In [0.5, 2].
  double coarse_min_registered_offset = 1.0;
  double coarse_margin = 0.02;  // [nats] Q of a coarse probe must lie this far below the pose's
  // [-] the coarse probe judges only poses whose classifier p is below this (and is only run
  // for them): a band above min_probability where p alone is unsure. A sensor the classifier
  // was not trained on puts its aligned pairs lower than the training pairs (ground truth
  // p 0.01-0.07 on HDL-64 scans split by elevation bands, doc/verdict_every_error.md), where a
  // fixed bound on p must choose between them and the errors; the probe decides by Q's shape
  // instead, and costs nothing for the pairs p is sure of. In (min_probability, 1]; 1 = every
  // pose.
  double coarse_below_probability = 1.0;
  // [-] loop closures only (loopClosureVerdict): the relative check's margin for these pairs;
  // < 0 = the stream's (RelativeCheckConfig::margin). A registration a little off (ICP
  // stopped 2-3 tolerances from a revisit) leaves a weaker slope than a one-tolerance step.
  double relative_margin = -1.0;
  // [tolerances] loop closures only: a candidate rejected at its pose is judged again at the
  // pose refined on Q within this many tolerances of it (refinement.hpp); when that pose
  // passes, it is offered (AlignmentVerdict::refined, refinement): the verdict stays
  // "misaligned" for the given pose, the back end may add the refined pose instead. A
  // registration that stopped a fraction of the tolerance from a true revisit is rejected at
  // its pose (Q is lower one tolerance on) but right once refined. In [0, 1]. 0 = off.
  double max_refinement = 0.0;
  // Loop closures only: a candidate accepted at its pose is registered again from starts
  // around it (restart_check.hpp, VerdictConfig::restart) and rejected when a pose at least
  // restart.min_distance tolerances away passes this verdict with a clearly lower Q: the
  // registration stopped off the revisit along repeated structure. That pose is offered as
  // a refined one (AlignmentVerdict::refined) when the classifier also says aligned there.
  bool restarts = false;
  // [tolerances] loop closures only: a candidate rejected at its pose is registered once from
  // it (restart_check.hpp registeredNearby, VerdictConfig::restart.registration); when the
  // registration ends within this many tolerances at a pose this verdict accepts (with its
  // restart check) and the classifier's p reaches registered_min_probability there, the
  // candidate is accepted: its pose is within the tolerance of an accepted alignment, which is
  // offered (AlignmentVerdict::refined). In [0, 1): a pose off by a full tolerance, registered
  // back, ends a tolerance away and stays rejected. 0 = off. Tried before max_refinement.
  double max_registered_offset = 0.0;
  // [-] with max_registered_offset: the classifier's p (Eq. 9) the registered pose must also
  // reach, besides this verdict's min_probability. lidar_2d: 0.5, the classifier's own
  // threshold (without it one more false Intel candidate passed, doc/loop_closure.md); 0 = the
  // verdict alone, which true 3D revisits need (their p is low at any pose: loop pairs are
  // far apart in time, the classifier was trained on consecutive ones). In [0, 1].
  double registered_min_probability = 0.0;
  std::string validate() const;  // empty when valid
};

struct VerdictConfig {
  VerdictMethod method = VerdictMethod::kClassifier;
  ClassifierConfig classifier;  // trained for `tolerance` (coral_train)
  ToleranceConfig tolerance;
  RelativeCheckConfig relative;
  GateConfig gate;  // method kGated: pairs of the stream (odometry)
  // Loop-closure candidates (check_alignment with loop_closure, coral_check --loop_closure):
  // pairs far apart in time, transform from the back end's own matcher. The same gated
  // verdict with this gate: true revisits look less alike than consecutive scans (viewpoint,
  // time), false ones are local optima of registration (doc/loop_closure.md).
  GateConfig loop_closure;
  FreeSpaceConfig free_space;  // the check behind max_free_space (either gate)
  RestartConfig restart;       // the check behind the loop gate's `restarts`
  // Measure the free-space and constraint terms even when `gate` does not use them
  // (evaluation: every term of every pair, coral_loop_eval); never changes a verdict.
  bool measure_gate_terms = false;
  std::string validate() const;  // empty when valid: every group of problemsByGroup()

  // The problems of each settings group, named as presets and the nodelet name the group
  // (classifier/ also holds the relative check's settings; restart/ the check's starts,
  // registration/ its registration). The one list validate() and
  // online::IntrospectorConfig::validate() walk, so that no group is validated by one and
  // forgotten by the other (free_space/ once was, and a bad bin_deg threw in the check).
  struct GroupProblems {
    const char* group;
    std::string problems;  // empty when valid
  };
  std::vector<GroupProblems> problemsByGroup() const;
};

// The verdict configuration of a loop-closure request: method kGated with the loop gate.
VerdictConfig loopClosureVerdict(const VerdictConfig& cfg);

struct AlignmentVerdict {
  CoralResult coral;             // at the given pose
  Verdict classifier;            // Eq. 9-10; meaningful when coral.valid
  RelativeCheckResult relative;  // filled by kRelative / kBoth
  // Measured when gate.max_free_space < 1 (whatever the method); invalid otherwise.
  FreeSpaceResult free_space;
  // Measured when gate.min_constraint > 0 (whatever the method); invalid otherwise.
  ConstraintResult constraint;
  // Measured when gate.coarse_max_multiple >= 2 or gate.coarse_registration and the method runs
  // the relative check (and it passed, unless measure_gate_terms); invalid otherwise.
  CoarseProbeResult coarse;
  bool valid = false;    // a verdict was reached
  bool aligned = false;  // not misaligned by the tolerance or more
  // Classifier p (Eq. 9); relative: relativeProbability(); both: the smaller of the two.
  double probability = 0.0;
  std::string reason;  // why there is no verdict (empty when valid)
  // valid and misaligned: which term said so, in words ("relative check: ...", "gate:
  // classifier p 2e-05 < 0.01", ...); empty when aligned.
  std::string rejected_by;
  // Gate max_refinement > 0 and rejected at the given pose: the walk on Q (refinement.hpp).
  // The verdict above is the given pose's either way; refined: the pose
  // T_a_b * refinement.delta passes (refinedPoseAccepted): an edge the back end may add
  // instead of the given one.
  PoseRefinement refinement;
  bool refined = false;
  // Gate `restarts` and accepted at the given pose: the second registration. When it found a
  // better alignment, the verdict is "misaligned" and refinement.delta leads to that pose.
  RestartResult restart;
  // Gate max_registered_offset > 0 and rejected at the given pose: the registration from it.
  // nearby.accepted: the verdict is "aligned" and refinement.delta leads to nearby.T_a_b.
  NearbyAlignment nearby;
};

// A monotone confidence in [0, 1] for the relative check, 0.5 at the margin: sigmoid(10 *
// (margin - score)). Not calibrated; it orders pairs (ROC) and fills `probability`.
double relativeProbability(const RelativeCheckResult& r, const RelativeCheckConfig& cfg);

// Whether the gate's coarse probe judges a pose of classifier p (coarse_below_probability).
bool coarseProbeJudges(const GateConfig& gate, double p);

// Whether the method kGated's coarse probe rejects a pose of classifier p that passed the
// relative check: it judges the pose and a probe's Q is lower by more than coarse_margin. With
// coarse.lowest_registered, the verdict's words are "a lower minimum of Q nearby", and the pose
// T_a_b * coarse.lowest.delta is that minimum (a front end's second try: ros_eval).
bool coarseProbeRejects(const GateConfig& gate, const CoarseProbeResult& coarse, double p);

// The absolute terms the gate reads besides the classifier's p, measured at the pose.
struct GateTerms {
  double overlap = 1.0;  // CorAl's overlap fraction
  // Q at the pose (Eq. 5) [nats]; -infinity = not measured (never rejects)
  double quality = -std::numeric_limits<double>::infinity();
  FreeSpaceResult free_space;   // invalid = not measured (never rejects)
  ConstraintResult constraint;  // invalid = not measured (never rejects)
  CoarseProbeResult coarse;     // invalid = not measured (never rejects)
};
// v.coral's overlap and Q, free space, constraint, coarse probe
GateTerms gateTerms(const AlignmentVerdict& v);

// Combines the opinions as `method` says (used by judgeAlignment and by evaluation); the
// gate (kGated) reads the classifier's p and `terms`.
void combineVerdict(VerdictMethod method, const Verdict& classifier,
                    const RelativeCheckResult& relative, const RelativeCheckConfig& cfg,
                    AlignmentVerdict* out, const GateConfig& gate = GateConfig(),
                    const GateTerms& terms = GateTerms());

// CorAl of b (its own sensor frame) moved into a's frame by T_a_b (a CoralPair: b is
// filtered in its own frame), then the verdict as cfg.method says; per-point entropies in
// the result's coral as coral.per_point says.
// Preconditions: coral.validate() and cfg.validate() are empty. Never throws.
AlignmentVerdict judgeAlignment(const Scan& a, const Scan& b, const Eigen::Isometry3d& T_a_b,
                                const CoralConfig& coral, const VerdictConfig& cfg);

// The same in two steps, for callers that evaluate the pair at more poses afterwards
// (online self-calibration): the CoralPair judgeAlignment builds for these configs (the
// relative check's probe sub-sample only when cfg.method uses it), and the verdict on it.
std::unique_ptr<CoralPair> prepareVerdictPair(const Scan& a, const Scan& b,
                                              const CoralConfig& coral, const VerdictConfig& cfg);
AlignmentVerdict judgeAlignment(const CoralPair& pair, const Eigen::Isometry3d& T_a_b,
                                const VerdictConfig& cfg);

// Whether the refined pose is offered (AlignmentVerdict::refined), from the verdict judged
// there (judgeAlignment with method kGated; evaluation recombines its kBoth one): it passes
// the gate,
// and the classifier says aligned there (p >= its threshold, Eq. 10), not only "not far
// off" (the gate's min_probability). The walk ends at a minimum of Q; a false candidate
// that ICP left near a local minimum also gets there and passes the relative check, but it
// does not look like an aligned pair: on the ACES loops the refined true candidates reach p
// 0.6-0.999, the false ones that pass the gate 0.01-0.4 (doc/loop_closure.md).
bool refinedPoseAccepted(const AlignmentVerdict& at_refined);

// The loop gate's max_registered_offset accepts a candidate at the pose registered from it when
// the verdict at that pose passes (valid and aligned, restart check included) and the
// classifier's p reaches gate.registered_min_probability there.
bool registeredPoseAccepted(const AlignmentVerdict& at_registered, const GateConfig& gate);

// What the restart check reads of a verdict judged at one pose (restart_check.hpp):
// {valid and aligned, Q, overlap}.
JudgedPose judgedPose(const AlignmentVerdict& v);

// The classifier as the nodelet's private parameters ~classifier/method, beta0, beta1, beta2,
// threshold (`<rosparam file=.../>` inside the nodelet, coral.launch classifier:=, coral_check
// --classifier). method is `classifier`: loaded over a preset whose default method is
// relative, the file is used rather than ignored. With `tolerance`, a tolerance/ section the
// classifier was trained for comes first (a classifier only holds for its tolerance).
// `comments` become leading # lines. Written by coral_train and by online self-calibration.
std::string classifierYaml(const ClassifierConfig& c, const std::vector<std::string>& comments,
                           const ToleranceConfig* tolerance = nullptr);

}  // namespace coral
}  // namespace coral_introspection
