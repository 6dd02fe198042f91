#include "coral_introspection/eval/perturbation.hpp"

#include "coral_introspection/coral/validation.hpp"

#include <cmath>
#include <sstream>

#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace eval {

PerturbationConfig PerturbationConfig::radarProtocol() { return PerturbationConfig(); }

PerturbationConfig PerturbationConfig::lidarProtocol() {
  PerturbationConfig c;
  c.translations = {0.1};  // Sec. IV: e_d = 0.1 m ...
  c.combined_yaw = 0.1;    // ... together with e_theta = 0.1 rad
  return c;
}

std::string PerturbationConfig::validate() const {
  coral::Problems p;
  p.require(!(translations.empty() && rotations.empty()),
            "translations and rotations are both empty: no misaligned samples");
  for (double t : translations) p.require(t > 0.0 && std::isfinite(t), "translations", "> 0 m", t);
  for (double r : rotations) p.require(r > 0.0 && r < M_PI, "rotations", "in (0, pi) rad", r);
  return p
      .require(combined_yaw >= 0.0 && combined_yaw < M_PI, "combined_yaw", "in [0, pi) rad",
               combined_yaw)
      .str();
}

std::string groupLabel(double translation_m, double yaw_rad) {
  std::ostringstream s;
  if (translation_m > 0.0) s << translation_m << " m";
  if (translation_m > 0.0 && yaw_rad > 0.0) s << " + ";
  if (yaw_rad > 0.0) s << yaw_rad << " rad";
  return s.str();
}

std::vector<Perturbation> makePerturbations(const PerturbationConfig& cfg) {
  std::vector<Perturbation> out;
  struct Dir {
    const char* name;
    double x, y, yaw_sign;
  };
  // Longitudinal (forward/backward) and lateral (left/right) offsets of Sec. V.
  const Dir dirs[4] = {
      {"forward", 1, 0, 1}, {"backward", -1, 0, -1}, {"left", 0, 1, 1}, {"right", 0, -1, -1}};
  for (double m : cfg.translations)
    for (const Dir& d : dirs) {
      Perturbation p;
      p.name = d.name;
      p.group = groupLabel(m, cfg.combined_yaw);
      p.dx = d.x * m;
      p.dy = d.y * m;
      p.dyaw = d.yaw_sign * cfg.combined_yaw;
      p.delta = coral::se2(p.dx, p.dy, p.dyaw);
      out.push_back(p);
    }
  for (double r : cfg.rotations)
    for (double sign : {1.0, -1.0}) {
      Perturbation p;
      p.name = sign > 0 ? "yaw+" : "yaw-";
      p.group = groupLabel(0.0, r);
      p.dyaw = sign * r;
      p.delta = coral::se2(0.0, 0.0, p.dyaw);
      out.push_back(p);
    }
  return out;
}

Eigen::Isometry3d perturb(const Eigen::Isometry3d& T_a_b, const Perturbation& p) {
  return T_a_b * p.delta;  // offset applied in the sensor frame of the later scan b
}

}  // namespace eval
}  // namespace coral_introspection
