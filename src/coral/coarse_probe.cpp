#include "coral_introspection/coral/coarse_probe.hpp"

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>

#include "coral_introspection/coral/relative_check.hpp"
#include "coral_introspection/coral/restart_check.hpp"

namespace coral_introspection {
namespace coral {

std::vector<ToleranceOffset> coarseOffsets(const ToleranceConfig& tol, int dimension,
                                           int max_multiple) {
  std::vector<ToleranceOffset> out;
  for (int multiple = 2; multiple <= max_multiple; multiple += 2) {
    ToleranceConfig scaled = tol;  // one "tolerance" of `multiple` tolerances
    scaled.translation *= multiple;
    scaled.rotation_deg *= multiple;
    for (ToleranceOffset o : toleranceOffsets(scaled, dimension)) {
      o.name += " x" + std::to_string(multiple);
      out.push_back(o);
    }
  }
  if (max_multiple < 2) return out;
  // Quarter and half turns about z (yaw): a corridor or a symmetric room seen turned round
  // is a minimum of Q that no step of a few tolerances leaves.
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
                              const ToleranceConfig& tol, int max_multiple,
                              const LazySurfaceTarget* registration, double min_registered_offset) {
  CoarseProbeResult r;
  if ((max_multiple < 2 && registration == nullptr) || !at_pose_probe.valid) return r;
  r.q = at_pose_probe.quality;
  // A probe with a lower Q than the lowest so far becomes the lowest.
  auto consider = [&r](double q, const ToleranceOffset& step, bool registered) {
    if (!std::isfinite(q) || (r.valid && q >= r.lowest_q)) return;
    r.valid = true;
    r.lowest_q = q;
    r.lowest = step;
    r.lowest_registered = registered;
  };
  const std::vector<ToleranceOffset> offsets = coarseOffsets(tol, dimension, max_multiple);
  const std::vector<double> q = neighbourQualities(pair, T_a_b, offsets);
  for (std::size_t i = 0; i < q.size(); ++i) consider(q[i], offsets[i], false);
  if (registration == nullptr) return r;
  // A registration from the pose converges into the minimum of Q a few centimetres wide that
  // fixed steps miss unless they land on it (errors between the steps' sizes): the loop
  // gate's registration from the pose, without a bound and without judging there.
  // (Unbounded, so never screened: only the registration config of the RestartConfig is used.)
  RestartConfig restart;
  restart.registration = registration->config();
  const NearbyAlignment reg = registeredNearby(
      pair, T_a_b, tol, restart, std::numeric_limits<double>::infinity(),
      [](const Eigen::Isometry3d&) { return true; }, &registration->get());
  r.registered = reg.usable;
  r.registered_size = reg.size;
  // Closer: the registration found the pose's own minimum (within what it resolves).
  if (!r.registered || r.registered_size < min_registered_offset) return r;
  const CoralResult at = pair.evaluateProbe(reg.T_a_b);
  ToleranceOffset step;
  step.delta = T_a_b.inverse() * reg.T_a_b;
  std::ostringstream name;
  name << std::setprecision(2) << "the pose registered from it (" << r.registered_size
       << " tolerances away)";
  step.name = name.str();
  if (at.valid) consider(at.quality, step, true);
  return r;
}

}  // namespace coral
}  // namespace coral_introspection
