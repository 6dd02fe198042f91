#include "coral_introspection/eval/loop_gates.hpp"

namespace coral_introspection {
namespace eval {

const std::vector<std::string>& loopGateNames() {
  static const std::vector<std::string> names = {
      "verdict",      "refined",      "no_free_space", "no_constraint", "relative", "classifier",
      "fitness<=0.3", "fitness<=0.5", "fitness<=2.5",  "oracle",        "all"};
  return names;
}

namespace {
bool isVerdictGate(const std::string& gate) {
  return gate == "verdict" || gate == "refined" || gate == "no_free_space" ||
         gate == "no_constraint";
}

// One kBoth evaluation combined as a CorAl gate decides (valid and aligned = accepted).
coral::AlignmentVerdict decide(const std::string& gate, const coral::AlignmentVerdict& v_both,
                               const coral::VerdictConfig& cfg) {
  coral::AlignmentVerdict v = v_both;
  if (!v_both.valid) return v;  // no CorAl verdict (no overlap): every CorAl gate rejects
  if (isVerdictGate(gate)) {
    coral::VerdictConfig loop = coral::loopClosureVerdict(cfg);
    if (gate == "no_free_space") loop.gate.max_free_space = 1.0;
    if (gate == "no_constraint") loop.gate.min_constraint = 0.0;
    // v_both's relative decision used the stream's margin: decide again with the loop's.
    v.relative.misaligned = coral::exceedsMargin(v.relative, loop.relative);
    coral::combineVerdict(loop.method, v.classifier, v.relative, loop.relative, &v, loop.gate,
                          coral::gateTerms(v));
    // The loop gate's restart check (coral_loop_eval runs it when the preset turns it on).
    if (v.aligned && v_both.restart.better_elsewhere) v.aligned = false;
    // Rejected at the pose, accepted at the pose registered from it within the loop gate's
    // max_registered_offset (judged there by the whole loop verdict, whatever this gate leaves
    // out).
    if (!v.aligned && v_both.nearby.accepted) v.aligned = true;
  } else if (gate == "relative") {
    coral::combineVerdict(coral::VerdictMethod::kRelative, v.classifier, v.relative, cfg.relative,
                          &v);
  } else if (gate == "classifier") {
    coral::combineVerdict(coral::VerdictMethod::kClassifier, v.classifier, v.relative, cfg.relative,
                          &v);
  } else {
    v.valid = false;  // not a CorAl gate
  }
  return v;
}

bool accepts(const coral::AlignmentVerdict& v) { return v.valid && v.aligned; }
}  // namespace

bool loopGateAccepts(const std::string& gate, const LoopCandidate& c,
                     const coral::AlignmentVerdict& v_both, const coral::VerdictConfig& cfg,
                     const coral::AlignmentVerdict* v_refined, bool* refined) {
  if (refined) *refined = false;
  if (gate == "oracle") return c.is_true;
  if (gate == "all") return true;
  if (gate.rfind("fitness<=", 0) == 0) return c.converged && c.fitness <= std::stod(gate.substr(9));
  if (accepts(decide(gate, v_both, cfg))) {
    // Accepted at the registered pose: a back end that adds offered poses adds that one.
    if (refined) *refined = gate == "refined" && v_both.nearby.accepted && v_refined != nullptr;
    return true;
  }
  // As coral::judgeAlignment offers it (coral::refinedPoseAccepted on the loop gate's verdict).
  if (gate != "refined" || !v_refined || !coral::refinedPoseAccepted(decide(gate, *v_refined, cfg)))
    return false;
  if (refined) *refined = true;
  return true;
}

}  // namespace eval
}  // namespace coral_introspection
