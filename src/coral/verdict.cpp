#include "coral_introspection/coral/verdict.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace coral {

const char* verdictMethodName(VerdictMethod m) {
  switch (m) {
    case VerdictMethod::kRelative:
      return "relative";
    case VerdictMethod::kBoth:
      return "both";
    case VerdictMethod::kGated:
      return "gated";
    default:
      return "classifier";
  }
}

bool parseVerdictMethod(const std::string& name, VerdictMethod* m) {
  for (VerdictMethod v : {VerdictMethod::kClassifier, VerdictMethod::kRelative,
                          VerdictMethod::kBoth, VerdictMethod::kGated})
    if (name == verdictMethodName(v)) {
      *m = v;
      return true;
    }
  return false;
}

std::string GateConfig::validate() const {
  return Problems()
      .require(min_probability >= 0.0 && min_probability < 1.0, "min_probability",
               "in [0, 1), 0 = off", min_probability)
      .require(min_overlap >= 0.0 && min_overlap < 1.0, "min_overlap", "in [0, 1), 0 = off",
               min_overlap)
      .require(max_free_space >= 0.0 && max_free_space <= 1.0, "max_free_space",
               "in [0, 1], 1 = off", max_free_space)
      .require(min_constraint >= 0.0, "min_constraint", ">= 0 tolerances^2, 0 = off",
               min_constraint)
      .require(constraint_beam_step_deg >= 0.0 && constraint_beam_step_deg <= 10.0,
               "constraint_beam_step_deg", "in [0, 10] deg, 0 = off", constraint_beam_step_deg)
      .require(!std::isnan(max_quality), "max_quality", "a number of nats, .inf = off", max_quality)
      .require(max_flat_axes >= -1 && max_flat_axes <= 2, "max_flat_axes",
               "in [-1, 2] (of x, y, yaw), -1 = off", max_flat_axes)
      .require(coarse_max_multiple == 0 || (coarse_max_multiple >= 2 && coarse_max_multiple <= 16),
               "coarse_max_multiple", "0 (off) or in [2, 16] tolerances", coarse_max_multiple)
      .require(coarse_margin >= 0.0 && std::isfinite(coarse_margin), "coarse_margin", ">= 0 nats",
               coarse_margin)
      .require(coarse_min_registered_offset >= 0.5 && coarse_min_registered_offset <= 2.0,
               "coarse_min_registered_offset", "in [0.5, 2] tolerances",
               coarse_min_registered_offset)
      .require(coarse_below_probability > min_probability && coarse_below_probability <= 1.0,
               "coarse_below_probability", "in (min_probability, 1], 1 = every pose",
               coarse_below_probability)
      .require(relative_margin < 2.0, "relative_margin", "< 2 (< 0: the relative check's)",
               relative_margin)
      .require(max_refinement >= 0.0 && max_refinement <= 1.0, "max_refinement",
               "in [0, 1] tolerances, 0 = off", max_refinement)
      .require(max_registered_offset >= 0.0 && max_registered_offset < 1.0, "max_registered_offset",
               "in [0, 1) tolerances, 0 = off", max_registered_offset)
      .require(registered_min_probability >= 0.0 && registered_min_probability <= 1.0,
               "registered_min_probability", "in [0, 1], 0 = the verdict alone",
               registered_min_probability)
      .str();
}

std::vector<VerdictConfig::GroupProblems> VerdictConfig::problemsByGroup() const {
  return {{"classifier", classifier.validate()},
          {"classifier", relative.validate()},  // relative_margin, flat_ratio, ...
          {"tolerance", tolerance.validate()},
          {"gate", gate.validate()},
          {"loop_closure", loop_closure.validate()},
          {"free_space", free_space.validate()},
          {"restart", restart.validateStarts()},
          {"registration", restart.registration.validate()}};
}

std::string VerdictConfig::validate() const {
  Problems p;
  for (const GroupProblems& g : problemsByGroup()) p.nested(g.group, g.problems);
  return p.str();
}

VerdictConfig loopClosureVerdict(const VerdictConfig& cfg) {
  VerdictConfig v = cfg;
  v.method = VerdictMethod::kGated;
  v.gate = cfg.loop_closure;
  if (cfg.loop_closure.relative_margin >= 0.0) v.relative.margin = cfg.loop_closure.relative_margin;
  return v;
}

namespace {
std::string number(double v) {
  std::ostringstream s;
  s << std::setprecision(3) << v;
  return s.str();
}

// Why the relative check calls the pose misaligned, in words.
std::string relativeRejection(const RelativeCheckResult& r, const RelativeCheckConfig& cfg) {
  std::string s = "relative check: score " + number(r.score) + " > margin " + number(cfg.margin);
  if (!r.hint.name.empty()) s += " (Q lower at " + r.hint.name + ")";
  return s;
}
}  // namespace

double relativeProbability(const RelativeCheckResult& r, const RelativeCheckConfig& cfg) {
  return r.valid ? sigmoid(10.0 * (cfg.margin - r.score)) : 0.0;
}

GateTerms gateTerms(const AlignmentVerdict& v) {
  return {v.coral.overlap, v.coral.quality, v.free_space, v.constraint, v.coarse};
}

bool coarseProbeJudges(const GateConfig& gate, double p) {
  return gate.coarse_below_probability >= 1.0 || p < gate.coarse_below_probability;
}

bool coarseProbeRejects(const GateConfig& gate, const CoarseProbeResult& coarse, double p) {
  return coarse.valid && coarseProbeJudges(gate, p) && coarse.drop() > gate.coarse_margin;
}

void combineVerdict(VerdictMethod method, const Verdict& classifier,
                    const RelativeCheckResult& relative, const RelativeCheckConfig& cfg,
                    AlignmentVerdict* out, const GateConfig& gate, const GateTerms& terms) {
  const bool rel_needed = method != VerdictMethod::kClassifier;
  if (rel_needed && !relative.valid) {
    out->valid = out->aligned = false;
    out->probability = 0.0;
    out->reason = "relative check without a valid Q at the tolerance neighbours";
    return;
  }
  const double p_rel = relativeProbability(relative, cfg);
  out->valid = true;
  out->reason.clear();
  out->rejected_by.clear();
  const std::string p_words = "classifier p " + number(classifier.probability);
  const std::vector<Axis> flat = horizontalFlatAxes(relative.flat_axes);  // the gate counts these
  switch (method) {
    case VerdictMethod::kClassifier:
      out->probability = classifier.probability;
      out->aligned = classifier.aligned;
      if (!out->aligned) out->rejected_by = p_words + " below its threshold";
      break;
    case VerdictMethod::kRelative:
      out->probability = p_rel;
      out->aligned = !relative.misaligned;
      if (!out->aligned) out->rejected_by = relativeRejection(relative, cfg);
      break;
    case VerdictMethod::kBoth:
      out->probability = std::min(classifier.probability, p_rel);
      out->aligned = classifier.aligned && !relative.misaligned;
      if (relative.misaligned)
        out->rejected_by = relativeRejection(relative, cfg);
      else if (!classifier.aligned)
        out->rejected_by = p_words + " below its threshold";
      break;
    case VerdictMethod::kGated:
      out->probability = p_rel;
      out->aligned = !relative.misaligned;
      if (relative.misaligned) {
        out->rejected_by = relativeRejection(relative, cfg);
      } else if (coarseProbeRejects(gate, terms.coarse, classifier.probability)) {
        out->aligned = false;
        // A fixed step found a minimum past the CorAl radius; the registration also one in a
        // valley of Q between the axes, which may lie within the radius
        // (doc/verdict_every_error.md "Errors between the axes").
        const bool registered = terms.coarse.lowest_registered;
        out->rejected_by = "gate: coarse probe: Q " + number(terms.coarse.drop()) +
                           " nats lower at " + terms.coarse.lowest.name +
                           (registered ? " (a lower minimum of Q nearby: off by the tolerance or "
                                         "more)"
                                       : " (a minimum of Q past the CorAl radius: off by more "
                                         "than the tolerance)");
      } else if (classifier.probability < gate.min_probability) {
        out->aligned = false;
        out->rejected_by = "gate: " + p_words + " < " + number(gate.min_probability) +
                           " (far from how aligned pairs look)";
      } else if (terms.overlap < gate.min_overlap) {
        out->aligned = false;
        out->rejected_by =
            "gate: overlap " + number(terms.overlap) + " < " + number(gate.min_overlap);
      } else if (gate.max_flat_axes >= 0 && static_cast<int>(flat.size()) > gate.max_flat_axes) {
        out->aligned = false;
        std::string names;
        for (Axis a : flat) names += std::string(names.empty() ? "" : ", ") + axisName(a);
        out->rejected_by = "gate: " + std::to_string(flat.size()) + " flat axes (" + names +
                           ") > " + std::to_string(gate.max_flat_axes) +
                           " (Q does not pin the pose along them)";
      } else if (terms.quality > gate.max_quality) {
        out->aligned = false;
        out->rejected_by = "gate: Q " + number(terms.quality) + " > " + number(gate.max_quality) +
                           " nats (the surfaces lie near each other but do not coincide)";
      } else if (terms.free_space.valid && terms.free_space.conflict > gate.max_free_space) {
        out->aligned = false;
        out->rejected_by = "gate: free-space conflict " + number(terms.free_space.conflict) +
                           " > " + number(gate.max_free_space) +
                           " (points of one scan where the other saw through)";
      } else if (terms.constraint.valid && terms.constraint.weakest < gate.min_constraint) {
        out->aligned = false;
        out->rejected_by = "gate: constraint " + number(terms.constraint.weakest) + " < " +
                           number(gate.min_constraint) +
                           " (the shared structure does not pin the pose: a corridor, a short "
                           "wall)";
      }
      if (!out->aligned) out->probability = std::min(p_rel, classifier.probability);
      break;
  }
}

std::unique_ptr<CoralPair> prepareVerdictPair(const Scan& a, const Scan& b,
                                              const CoralConfig& coral, const VerdictConfig& cfg) {
  const bool rel_needed = cfg.method != VerdictMethod::kClassifier;
  return std::make_unique<CoralPair>(a, b, coral, rel_needed ? cfg.relative.probe_queries : 0);
}

AlignmentVerdict judgeAlignment(const Scan& a, const Scan& b, const Eigen::Isometry3d& T_a_b,
                                const CoralConfig& coral, const VerdictConfig& cfg) {
  return judgeAlignment(*prepareVerdictPair(a, b, coral, cfg), T_a_b, cfg);
}

namespace {
// The verdict at one pose, no refinement.
// `target`: a's registration target shared by the checks of one verdict (built when first
// needed). `registered`: T_a_b is where a registration of this pair ended
// (the restart check's, the registration from a rejected candidate's pose): the coarse probe
// does not register from it again (it would end where it starts; 12-20 ms on a 64-beam pair).
AlignmentVerdict judgeAtPose(const CoralPair& pair, const Eigen::Isometry3d& T_a_b,
                             const VerdictConfig& cfg, const LazySurfaceTarget& target,
                             bool registered = false) {
  AlignmentVerdict v;
  // One prepared pair for every pose: the relative check's Q values and the Q at the pose
  // come from the same filtered points and queries (coral_pair.hpp).
  const bool rel_needed = cfg.method != VerdictMethod::kClassifier;
  const CoralConfig& coral = pair.config();
  CoralResult at_pose_probe;
  v.coral = pair.evaluate(T_a_b, rel_needed ? &at_pose_probe : nullptr);
  if (!v.coral.valid) {
    v.reason = "CorAl has no valid result (overlap " + std::to_string(v.coral.overlap) + ")";
    return v;
  }
  v.classifier = classify(cfg.classifier, v.coral.h_joint, v.coral.h_sep);  // Eq. 9-10
  if (rel_needed)
    v.relative =
        relativeCheck(pair, T_a_b, at_pose_probe, coral.dimension, cfg.tolerance, cfg.relative);
  if (cfg.gate.max_free_space < 1.0 || cfg.measure_gate_terms)
    v.free_space = freeSpaceConflict(pair.points(0), pair.origin(0), pair.points(1), pair.origin(1),
                                     T_a_b, coral.dimension, cfg.free_space);
  if (cfg.gate.min_constraint > 0.0 || cfg.measure_gate_terms)
    v.constraint = registrationConstraint(pair.points(0), pair.points(1), T_a_b, coral,
                                          cfg.tolerance, cfg.gate.constraint_beam_step_deg);
  // Not when the relative check already rejects (its probes cost 2 x axes x steps + 3 and a
  // registration), nor where p is above the probe's band; an invalid result when the gate asks
  // for neither.
  if (rel_needed &&
      ((!v.relative.misaligned && coarseProbeJudges(cfg.gate, v.classifier.probability)) ||
       cfg.measure_gate_terms)) {
    const bool registers = cfg.gate.coarse_registration && !registered;
    v.coarse = coarseProbe(pair, T_a_b, at_pose_probe, coral.dimension, cfg.tolerance,
                           cfg.gate.coarse_max_multiple, registers ? &target : nullptr,
                           cfg.gate.coarse_min_registered_offset);
  }
  combineVerdict(cfg.method, v.classifier, v.relative, cfg.relative, &v, cfg.gate, gateTerms(v));
  return v;
}

// Whether verdict v at the given pose is a rejection of the gated verdict, after which
// judgeAlignment may look for a nearby pose (gate max_registered_offset, max_refinement).
bool gatedRejection(const AlignmentVerdict& v, const VerdictConfig& cfg) {
  return cfg.method == VerdictMethod::kGated && v.valid && !v.aligned;
}

// v's refinement leads from T_a_b to T, size tolerances away, Q q_start there and q_end at T.
void setRefinement(const Eigen::Isometry3d& T_a_b, const Eigen::Isometry3d& T, double size,
                   double q_start, double q_end, AlignmentVerdict* v) {
  v->refinement.valid = true;
  v->refinement.delta = T_a_b.inverse() * T;
  v->refinement.size = size;
  v->refinement.q_start = q_start;
  v->refinement.q_end = q_end;
}

// Gate `restarts` on verdict v, accepted at T_a_b: registered again from other starts
// (restart_check.hpp); a better alignment elsewhere rejects v and is offered when the
// classifier says aligned there too (refinedPoseAccepted), as a refined pose is.
// `target`: a's registration target, shared with the other checks of this verdict.
void checkRestarts(const CoralPair& pair, const Eigen::Isometry3d& T_a_b, const VerdictConfig& cfg,
                   AlignmentVerdict* v, const LazySurfaceTarget& target) {
  v->restart = betterAlignmentElsewhere(
      pair, T_a_b, judgedPose(*v), cfg.tolerance, cfg.restart,
      [&](const Eigen::Isometry3d& T) {
        return judgedPose(judgeAtPose(pair, T, cfg, target, true));
      },
      &target.get());
  const RestartResult& r = v->restart;
  if (!r.better_elsewhere) return;
  // Judged again at the pose the check chose (rarely: only when it rejects) rather than
  // mirroring its choice in the judge above.
  const AlignmentVerdict best = judgeAtPose(pair, r.T_a_b, cfg, target, true);
  v->aligned = false;
  // The local terms still say aligned; at most 0.5 so that the probability does not read
  // as a confident "aligned" for a rejected candidate.
  v->probability = std::min(v->probability, 0.5);
  setRefinement(T_a_b, r.T_a_b, r.distance, r.q_candidate, r.q, v);
  v->refined = refinedPoseAccepted(best);
  v->rejected_by = "restarts: registered again from " + std::to_string(r.starts) +
                   " starts, a pose " + number(r.distance) + " tolerances away passes with Q " +
                   number(r.q) + " < " + number(r.q_candidate) +
                   " (the registration stopped off the revisit); " +
                   (v->refined ? "offered (transform_a_b * correction)"
                               : "not offered: classifier p " +
                                     number(best.classifier.probability) + " below its threshold");
}

// Gate max_registered_offset on verdict v, rejected at T_a_b: registered once from the pose
// (restart_check.hpp registeredNearby). True when the registered pose, within the bound, passes
// the verdict (restart check included) with the classifier's p at least
// registered_min_probability there: v is then "aligned" with that pose offered.
bool acceptNearby(const CoralPair& pair, const Eigen::Isometry3d& T_a_b, const VerdictConfig& cfg,
                  AlignmentVerdict* v, const LazySurfaceTarget& target) {
  AlignmentVerdict w;
  v->nearby = registeredNearby(
      pair, T_a_b, cfg.tolerance, cfg.restart, cfg.gate.max_registered_offset,
      [&](const Eigen::Isometry3d& T) {
        w = judgeAtPose(pair, T, cfg, target, true);
        if (cfg.gate.restarts && w.valid && w.aligned) checkRestarts(pair, T, cfg, &w, target);
        return registeredPoseAccepted(w, cfg.gate);
      },
      &target.get());
  const NearbyAlignment& n = v->nearby;
  if (!n.accepted) return false;
  v->aligned = v->refined = true;
  v->probability = w.probability;
  v->rejected_by.clear();
  setRefinement(T_a_b, n.T_a_b, n.size, v->coral.quality, w.coral.quality, v);
  return true;
}
}  // namespace

AlignmentVerdict judgeAlignment(const CoralPair& pair, const Eigen::Isometry3d& T_a_b,
                                const VerdictConfig& cfg) {
  // One registration target for every check below that registers (built when first needed).
  const LazySurfaceTarget target(pair.points(0), pair.config(), cfg.restart.registration);
  AlignmentVerdict v = judgeAtPose(pair, T_a_b, cfg, target);
  if (cfg.method == VerdictMethod::kGated && cfg.gate.restarts && v.valid && v.aligned) {
    checkRestarts(pair, T_a_b, cfg, &v, target);
    return v;
  }
  if (!gatedRejection(v, cfg)) return v;
  if (cfg.gate.max_registered_offset > 0.0 && acceptNearby(pair, T_a_b, cfg, &v, target)) return v;
  if (!(cfg.gate.max_refinement > 0.0)) return v;
  v.refinement =
      refinePose(pair, T_a_b, pair.config().dimension, cfg.tolerance, cfg.gate.max_refinement);
  if (!(v.refinement.size > 0.0)) return v;  // Q has no lower pose within reach
  // The verdict stays the given pose's: a pose off by the tolerance or more is never called
  // aligned because a better one lies nearby. The refined pose is offered with its own
  // verdict (doc/loop_closure.md: accepting it in place of the given pose also accepted
  // relations moved by 1-2 tolerances onto other minima of Q that look aligned).
  const AlignmentVerdict w = judgeAtPose(pair, T_a_b * v.refinement.delta, cfg, target);
  v.refined = refinedPoseAccepted(w);
  std::string why = w.valid ? w.rejected_by : w.reason;
  if (why.empty())  // passed the gate, not the classifier's own threshold
    why = "classifier p " + number(w.classifier.probability) +
          " below its threshold (a pose at Q's minimum must look aligned)";
  v.rejected_by += "; at the pose refined by " + number(v.refinement.size) +
                   " tolerances: " + (v.refined ? "passes (transform_a_b * correction)" : why);
  return v;
}

JudgedPose judgedPose(const AlignmentVerdict& v) {
  return {v.valid && v.aligned, v.coral.quality, v.coral.overlap};
}

bool refinedPoseAccepted(const AlignmentVerdict& at_refined) {
  return at_refined.valid && at_refined.aligned && at_refined.classifier.aligned;
}

bool registeredPoseAccepted(const AlignmentVerdict& at_registered, const GateConfig& gate) {
  return at_registered.valid && at_registered.aligned &&
         at_registered.classifier.probability >= gate.registered_min_probability;
}

std::string classifierYaml(const ClassifierConfig& c, const std::vector<std::string>& comments,
                           const ToleranceConfig* tolerance) {
  std::ostringstream s;
  for (const std::string& line : comments) s << "# " << line << '\n';
  s << std::setprecision(12);
  if (tolerance)
    s << "tolerance:\n  translation: " << tolerance->translation
      << "\n  rotation_deg: " << tolerance->rotation_deg << '\n';
  // Nested under "classifier" = the nodelet's ~classifier/beta0 ... (Eq. 9-10).
  s << "classifier:\n  method: " << verdictMethodName(VerdictMethod::kClassifier)
    << "\n  beta0: " << c.beta0 << "\n  beta1: " << c.beta1 << "\n  beta2: " << c.beta2
    << "\n  threshold: " << c.threshold << '\n';
  return s.str();
}

}  // namespace coral
}  // namespace coral_introspection
