#include "coral_introspection/coral/coarse_probe.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

#include "coral_introspection/coral/refinement.hpp"
#include "coral_introspection/coral/registration.hpp"
#include "coral_introspection/coral/relative_check.hpp"

namespace coral_introspection {
namespace coral {

std::vector<ToleranceOffset> coarseOffsets(const ToleranceConfig& tol, int dimension, int levels) {
  std::vector<ToleranceOffset> out;
  for (int level = 1, multiple = 2; level <= levels; ++level, multiple *= 2) {
    ToleranceConfig scaled = tol;  // one "tolerance" of `multiple` tolerances
    scaled.translation *= multiple;
    scaled.rotation_deg *= multiple;
    for (ToleranceOffset o : toleranceOffsets(scaled, dimension)) {
      o.name += " x" + std::to_string(multiple);
      out.push_back(o);
    }
  }
  if (levels <= 0) return out;
  // Quarter and half turns about z (yaw): a corridor or a symmetric room seen turned round
  // is a minimum of Q that no step of a few tolerances leaves (multiple 0: not a step size).
  for (double deg : {90.0, -90.0, 180.0}) {
    ToleranceOffset o;
    o.axis = Axis::kYaw;
    o.sign = deg > 0.0 ? 1 : -1;
    o.name = deg == 180.0 ? "yaw 180 deg" : (deg > 0.0 ? "yaw+ 90 deg" : "yaw- 90 deg");
    o.delta.linear() =
        Eigen::AngleAxisd(deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    out.push_back(o);
  }
  return out;
}

CoarseProbeResult coarseProbe(const CoralPair& pair, const Eigen::Isometry3d& T_a_b,
                              const CoralResult& at_pose_probe, int dimension,
                              const ToleranceConfig& tol, int levels,
                              const RegistrationConfig* registration) {
  CoarseProbeResult r;
  if ((levels <= 0 && registration == nullptr) || !at_pose_probe.valid) return r;
  const std::vector<ToleranceOffset> offsets = coarseOffsets(tol, dimension, levels);
  const std::vector<double> q = neighbourQualities(pair, T_a_b, offsets);
  r.q = at_pose_probe.quality;
  r.coral_evaluations = static_cast<int>(offsets.size());
  const std::size_t per_level = 2 * toleranceAxes(dimension).size();
  for (std::size_t i = 0; i < q.size(); ++i) {
    if (!std::isfinite(q[i]) || (r.valid && q[i] >= r.lowest_q)) continue;
    r.valid = true;
    r.lowest_q = q[i];
    r.lowest = offsets[i];
    // level i / per_level + 1 steps 2^level tolerances; the turns after the levels: 0
    r.multiple = i < per_level * static_cast<std::size_t>(levels) ? 2 << (i / per_level) : 0;
  }
  if (registration == nullptr) return r;
  // A registration from the pose converges into the minimum of Q a few centimetres wide that
  // fixed steps miss unless they land on it (errors between the steps' sizes).
  const SurfaceTarget target(pair.points(0), pair.config(), *registration);
  const RegistrationResult reg = target.align(pair.points(1), T_a_b);
  r.registered = reg.usable(*registration);
  if (!r.registered) return r;
  r.registered_size = toleranceSize(T_a_b.inverse() * reg.T_a_b, tol);
  if (r.registered_size < 1.0) return r;  // within the tolerance: no other pose found
  const CoralResult at = pair.evaluateProbe(reg.T_a_b);
  ++r.coral_evaluations;
  if (!at.valid || (r.valid && at.quality >= r.lowest_q)) return r;
  r.valid = true;
  r.lowest_q = at.quality;
  r.lowest = ToleranceOffset();
  r.lowest.delta = T_a_b.inverse() * reg.T_a_b;
  std::ostringstream name;
  name << std::setprecision(2) << "the pose registered from it (" << r.registered_size
       << " tolerances away)";
  r.lowest.name = name.str();
  r.multiple = 0;
  return r;
}

}  // namespace coral
}  // namespace coral_introspection
