#include "coral_introspection/coral/refinement.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace coral_introspection {
namespace coral {

double toleranceSize(const Eigen::Isometry3d& delta, const ToleranceConfig& tol) {
  const double angle = Eigen::AngleAxisd(delta.linear()).angle() * 180.0 / M_PI;
  return std::max(delta.translation().norm() / tol.translation, angle / tol.rotation_deg);
}

PoseRefinement refinePose(const CoralPair& pair, const Eigen::Isometry3d& T_a_b, int dimension,
                          const ToleranceConfig& tol, double max_size) {
  PoseRefinement r;
  const CoralResult start = pair.evaluateProbe(T_a_b);
  if (!start.valid) return r;
  r.valid = true;
  r.q_start = r.q_end = start.quality;
  if (!(max_size > 0.0)) return r;
  // Small slack: a step that lands exactly on the bound is within it.
  const double bound = max_size * (1.0 + 1e-9);
  for (double h : {max_size / 2.0, max_size / 4.0}) {
    ToleranceConfig step = tol;  // offsets of h tolerances along each axis
    step.translation *= h;
    step.rotation_deg *= h;
    const std::vector<ToleranceOffset> offsets = toleranceOffsets(step, dimension);
    for (int move = 0; move < kMaxMovesPerStep; ++move) {
      int best = -1;
      double best_q = r.q_end;
      for (std::size_t i = 0; i < offsets.size(); ++i) {
        const Eigen::Isometry3d delta = r.delta * offsets[i].delta;
        if (toleranceSize(delta, tol) > bound) continue;  // never past max_size
        const CoralResult c = pair.evaluateProbe(T_a_b * delta);
        if (c.valid && c.quality < best_q) {
          best_q = c.quality;
          best = static_cast<int>(i);
        }
      }
      if (best < 0) break;  // a minimum of Q at this step size (or nothing reachable)
      r.delta = r.delta * offsets[best].delta;
      r.q_end = best_q;
    }
  }
  r.size = toleranceSize(r.delta, tol);
  return r;
}

}  // namespace coral
}  // namespace coral_introspection
