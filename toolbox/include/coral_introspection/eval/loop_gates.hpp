// The gates a SLAM back end can put between "a registered loop candidate" and "add the
// edge" (doc/loop_closure.md), decided from one CorAl evaluation of the candidate
// (judged with method `both`, so the classifier and the relative check are both filled, and
// with every gate term measured, VerdictConfig::measure_gate_terms):
//   verdict      coral::loopClosureVerdict: relative check + the loop gate (this package)
//   refined      a back end that also adds the refined pose the verdict offers for a
//                candidate it rejects (AlignmentVerdict::refined, loop_closure/max_refinement)
//   no_free_space  the same without the gate's free-space term (what that term adds)
//   no_constraint  the same without the gate's constraint term (what that term adds)
//   relative     the relative check alone (the previous default)
//   classifier   the classifier alone at its threshold
//   fitness<=X   PCL's ICP fitness score at thresholds ROS SLAM packages ship: LIO-SAM 0.3,
//                hdl_graph_slam 0.5 (code) and 2.5 (a shipped launch file)
//   oracle       the reference's label (true within the tolerance)
//   all          every candidate
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/coral/verdict.hpp"
#include "coral_introspection/eval/loop_candidates.hpp"

namespace coral_introspection {
namespace eval {

const std::vector<std::string>& loopGateNames();

// Whether `gate` (one of loopGateNames()) accepts candidate c whose CorAl evaluation is
// v_both (method kBoth), with the preset's verdict configuration cfg; the verdict gates
// also reject it when v_both.restart found a better alignment elsewhere (the loop gate's
// restart check, run by the caller) and accept it when v_both.nearby was accepted (the loop
// gate's max_registered_offset, run by the caller). v_refined: the same evaluation at the
// candidate's refined pose (coral::refinePose within the loop gate's max_refinement, or the
// registered pose of v_both.nearby) when the verdict rejects at the pose; gate `refined`
// accepts the candidate there when the verdict would offer it (coral::refinedPoseAccepted)
// and sets *refined (the edge is then the refined pose).
bool loopGateAccepts(const std::string& gate, const LoopCandidate& c,
                     const coral::AlignmentVerdict& v_both, const coral::VerdictConfig& cfg,
                     const coral::AlignmentVerdict* v_refined = nullptr, bool* refined = nullptr);

}  // namespace eval
}  // namespace coral_introspection
