// Refinement of a loop-closure candidate's pose within the tolerance (the loop gate's
// max_refinement, verdict.hpp). A registration that stopped 0.1-0.3 m from a true revisit is
// within the tolerance, yet the relative check finds a lower Q one tolerance closer to the
// truth and the classifier's p is already low there (doc/loop_closure.md): the candidate is
// right, its pose not yet at Q's minimum. Walking Q downhill by steps of a fraction of the
// tolerance, never further than max_size tolerances from the given pose, reaches that
// minimum; the verdict judged there says whether the refined pose is offered to the back end
// (the verdict itself stays the given pose's, verdict.hpp). The walk only uses Q (Eq. 5)
// over the pair's probe queries, as the relative check does: no new term.
#pragma once

#include <Eigen/Geometry>

#include "coral_introspection/coral/coral_pair.hpp"
#include "coral_introspection/coral/tolerance.hpp"

namespace coral_introspection {
namespace coral {

// The size of an offset in tolerances: the larger of |t| / translation tolerance and its
// rotation angle / rotation tolerance ("off by at least the tolerance in translation or in
// rotation" is size >= 1).
double toleranceSize(const Eigen::Isometry3d& delta, const ToleranceConfig& tol);

struct PoseRefinement {
  // In b's sensor frame, as the tolerance offsets: the refined pose is T_a_b * delta.
  Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
  double size = 0.0;     // toleranceSize(delta): 0 = no lower Q within reach
  double q_start = 0.0;  // Q (probe queries) at the given pose [nats]
  double q_end = 0.0;    // at the refined pose
  bool valid = false;    // Q at the given pose was valid
};

// Pattern search on Q: from T_a_b, the lowest of the +-h steps along every axis of
// toleranceAxes(dimension) is taken while it lowers Q and keeps the total offset within
// max_size tolerances; h = max_size / 2, then max_size / 4, at most kMaxMovesPerStep moves
// each. max_size <= 0: no walk (size 0). Never throws.
PoseRefinement refinePose(const CoralPair& pair, const Eigen::Isometry3d& T_a_b, int dimension,
                          const ToleranceConfig& tol, double max_size);
constexpr int kMaxMovesPerStep = 4;

}  // namespace coral
}  // namespace coral_introspection
