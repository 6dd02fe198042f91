#include "coral_introspection/eval/restart_check.hpp"

#include <cmath>

#include "coral_introspection/coral/refinement.hpp"
#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace eval {

std::string RestartConfig::validate() const {
  bool radii_ok = !radii.empty();
  for (double r : radii) radii_ok = radii_ok && std::isfinite(r) && r > 0.0;
  return coral::Problems()
      .require(radii_ok, "radii", "non-empty, each > 0", radii.size())
      .require(directions >= 1, "directions", ">= 1", directions)
      .require(min_distance > 0.0, "min_distance", "> 0 tolerances", min_distance)
      .require(max_q_ratio > 0.0 && max_q_ratio <= 1.0, "max_q_ratio", "in (0, 1]", max_q_ratio)
      .str();
}

RestartResult betterAlignmentElsewhere(
    const coral::CoralPair& pair, const coral::Points& a, const coral::Points& b,
    const Eigen::Isometry3d& T_a_b, const coral::AlignmentVerdict& v,
    const coral::VerdictConfig& judge, const LoopCandidateConfig& registration,
    const std::function<bool(const coral::AlignmentVerdict&)>& accepts, const RestartConfig& cfg) {
  const coral::ToleranceConfig& tolerance = judge.tolerance;
  RestartResult out;
  out.q_candidate = v.coral.quality;
  if (!v.valid) return out;
  // "Clearly lower": by a share of |Q| (Q may be slightly negative on clean walls).
  const double bound = v.coral.quality - (1.0 - cfg.max_q_ratio) * std::abs(v.coral.quality);
  double best_q = bound;
  for (double radius : cfg.radii)
    for (int k = 0; k < cfg.directions; ++k) {
      const double angle = 2.0 * M_PI * k / cfg.directions;
      Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
      start.translation() =
          radius * tolerance.translation * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.0);
      LoopCandidate r;
      registerPair(a, b, T_a_b * start, registration, &r);
      ++out.starts;
      if (!r.converged) continue;
      ++out.converged;
      const double distance = coral::toleranceSize(T_a_b.inverse() * r.T_a_b, tolerance);
      if (distance < cfg.min_distance) continue;  // back at the candidate's pose
      const coral::AlignmentVerdict w = coral::judgeAlignment(pair, r.T_a_b, judge);
      if (!w.valid || !(w.coral.quality < best_q) || !accepts(w)) continue;
      best_q = w.coral.quality;
      out.better_elsewhere = true;
      out.T_a_b = r.T_a_b;
      out.distance = distance;
      out.q = w.coral.quality;
    }
  return out;
}

}  // namespace eval
}  // namespace coral_introspection
