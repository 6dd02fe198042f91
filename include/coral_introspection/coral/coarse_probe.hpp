// CorAl's Q (Eq. 5) at poses 2, 4, 6 ... tolerances, a quarter and a half turn away from the
// given pose, and at the pose a registration from it reaches (the gated verdict's coarse
// probe, GateConfig::coarse_max_multiple, coarse_registration). The relative check
// (relative_check.hpp) compares Q only with poses one tolerance away; past the CorAl radius Q
// falls again, so a pose two or more tolerances off often sits on a local minimum of Q that a
// one-tolerance step cannot leave, while a step of the error's own size lands at (or near)
// the truth, where Q is lower. On the ACES log 92 % of the errors the gated verdict accepted
// had Q above the ground truth's (median +0.1 nats); most were 2 tolerances along a corridor.
// The minimum at the truth is a few centimetres wide: errors between the steps' sizes are
// found by the registration, which converges into it (doc/verdict_every_error.md).
#pragma once

#include <limits>
#include <vector>

#include "coral_introspection/coral/coral_pair.hpp"
#include "coral_introspection/coral/registration.hpp"
#include "coral_introspection/coral/tolerance.hpp"

namespace coral_introspection {
namespace coral {

struct CoarseProbeResult {
  bool valid = false;  // probed: a Q at the pose and at least one valid probe
  double q = std::numeric_limits<double>::quiet_NaN();         // Q at the pose (probe queries)
  double lowest_q = std::numeric_limits<double>::quiet_NaN();  // lowest Q among the probes
  ToleranceOffset lowest;          // that probe's step (delta in b's frame; name "x+ x2", ...)
  bool lowest_registered = false;  // that probe is the registered pose, not a fixed step
  bool registered = false;         // a registration from the pose gave a pose (when asked)
  double registered_size = 0.0;    // its distance from the pose [tolerances] (toleranceSize)
  // How much lower Q is at the lowest probe than at the pose [nats] (> 0: lower away).
  double drop() const { return valid ? q - lowest_q : 0.0; }
};

// The steps probed up to `max_multiple` tolerances: both signs of every axis of
// toleranceAxes(dimension) at 2, 4, 6, ... <= max_multiple tolerances, size by size ("x+ x2",
// "x- x2", ..., "yaw- x10"), then turns of +90, -90 and 180 deg about z ("yaw+ 90 deg",
// "yaw- 90 deg", "yaw 180 deg"): a corridor or a symmetric room seen turned round is a
// minimum no step of a few tolerances leaves. None for max_multiple < 2.
std::vector<ToleranceOffset> coarseOffsets(const ToleranceConfig& tol, int dimension,
                                           int max_multiple);

// Q (the pair's probe queries, as the relative check) at T_a_b * delta for every step of
// coarseOffsets; `at_pose_probe` is the pair's Q at T_a_b over the same queries, reused.
// With `registration` (a's target, built when first needed), b is also registered onto a once
// from T_a_b (restart_check.hpp registeredNearby, without a bound) and the result, when usable
// and at least `min_registered_offset` tolerances away (GateConfig::coarse_min_registered_offset),
// is one more probe. No steps and no registration, or no valid Q at the pose: an invalid result,
// nothing evaluated.
CoarseProbeResult coarseProbe(const CoralPair& pair, const Eigen::Isometry3d& T_a_b,
                              const CoralResult& at_pose_probe, int dimension,
                              const ToleranceConfig& tol, int max_multiple,
                              const LazySurfaceTarget* registration = nullptr,
                              double min_registered_offset = 1.0);

}  // namespace coral
}  // namespace coral_introspection
