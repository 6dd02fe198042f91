// A second registration from several starts, the check a back end may run on a loop candidate
// the verdict accepts (coral_loop_eval --restarts, doc/loop_closure.md): ICP converged at the
// candidate's pose, a local optimum; registered again from starts around it, a right candidate
// comes back to it or ends at worse poses, while one registered a metre off along repeated
// structure (Intel's cubicle rows, ACES's corridors) finds the revisit's true pose, which is
// judged aligned and fits clearly better (lower Q, Eq. 5). CorAl's Q alone cannot find it:
// its minimum at the true pose is a few centimetres wide, narrower than any probe step that
// keeps the search affordable, while a registration converges into it. Evaluation toolbox
// (PCL registration through eval::registerPair); nothing here throws.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "coral_introspection/coral/coral_pair.hpp"
#include "coral_introspection/coral/verdict.hpp"
#include "coral_introspection/eval/loop_candidates.hpp"

namespace coral_introspection {
namespace eval {

struct RestartConfig {
  // Starts: the candidate's pose moved in b's x-y plane by each radius [tolerances, i.e.
  // multiples of tolerance/translation] in `directions` evenly spaced directions.
  std::vector<double> radii = {2.5, 4.0};
  int directions = 8;
  // A better alignment elsewhere: a registration result at least min_distance tolerances
  // (coral::toleranceSize) from the candidate's pose that the loop verdict accepts and whose
  // Q is below the candidate's by at least (1 - max_q_ratio) |Q|.
  double min_distance = 2.0;
  double max_q_ratio = 0.8;
  std::string validate() const;  // empty when valid
};

struct RestartResult {
  bool better_elsewhere = false;  // a better alignment was found (the candidate is rejected)
  Eigen::Isometry3d T_a_b = Eigen::Isometry3d::Identity();  // the best one found, if any
  double distance = 0.0;  // its distance from the candidate's pose [tolerances]
  double q = 0.0;         // its Q (the candidate's: q_candidate) [nats]
  double q_candidate = 0.0;
  int starts = 0, converged = 0;  // registrations run and converged
};

// For the candidate T_a_b of scans a and b (their sensor frames) whose verdict (judged on
// `pair` with `judge`, whose tolerance sizes the starts and the distances) is v: registers b
// onto a from every start with `registration` (eval::registerPair) and judges each result on
// `pair`; `accepts` decides whether the loop verdict accepts a judged pose (as the candidate's
// was). Preconditions: cfg.validate() and registration.validate() are empty.
RestartResult betterAlignmentElsewhere(
    const coral::CoralPair& pair, const coral::Points& a, const coral::Points& b,
    const Eigen::Isometry3d& T_a_b, const coral::AlignmentVerdict& v,
    const coral::VerdictConfig& judge, const LoopCandidateConfig& registration,
    const std::function<bool(const coral::AlignmentVerdict&)>& accepts, const RestartConfig& cfg);

}  // namespace eval
}  // namespace coral_introspection
