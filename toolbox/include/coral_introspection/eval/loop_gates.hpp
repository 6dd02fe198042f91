// The gates a SLAM back end can put between "a registered loop candidate" and "add the
// edge" (doc/loop_closure.md), decided from one CorAl evaluation of the candidate
// (judged with method `both`, so the classifier and the relative check are both filled, and
// with every gate term measured, VerdictConfig::measure_gate_terms):
//   verdict      coral::loopClosureVerdict: relative check + the loop gate (this package),
//                a candidate rejected at its pose judged again at its refined pose when the
//                gate's max_refinement is set (coral/refinement.hpp)
//   no_refinement  the verdict judged at the candidate's pose only (what refining adds)
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
// v_both (method kBoth), with the preset's verdict configuration cfg. v_refined: the same
// evaluation at the candidate's refined pose (coral::refinePose within the loop gate's
// max_refinement) when the verdict rejects at the pose; the verdict gates that reject at
// the pose decide again there, as coral::judgeAlignment does, and set *refined when they
// accept there (the edge is then the refined pose).
bool loopGateAccepts(const std::string& gate, const LoopCandidate& c,
                     const coral::AlignmentVerdict& v_both, const coral::VerdictConfig& cfg,
                     const coral::AlignmentVerdict* v_refined = nullptr, bool* refined = nullptr);

}  // namespace eval
}  // namespace coral_introspection
