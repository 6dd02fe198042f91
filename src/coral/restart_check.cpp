#include "coral_introspection/coral/restart_check.hpp"

#include <cmath>

#include "coral_introspection/coral/refinement.hpp"
#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace coral {

std::string RestartConfig::validate() const {
  bool radii_ok = !radii.empty();
  for (double r : radii) radii_ok = radii_ok && std::isfinite(r) && r > 0.0;
  return Problems()
      .require(radii_ok, "radii", "non-empty, each > 0", radii.size())
      .require(directions >= 1, "directions", ">= 1", directions)
      .require(min_distance > 0.0, "min_distance", "> 0 tolerances", min_distance)
      .require(max_q_ratio > 0.0 && max_q_ratio <= 1.0, "max_q_ratio", "in (0, 1]", max_q_ratio)
      .require(min_overlap_ratio >= 0.0 && min_overlap_ratio <= 1.0, "min_overlap_ratio",
               "in [0, 1]", min_overlap_ratio)
      .require(std::isfinite(coarse_min_step) && coarse_min_step > 0.0, "coarse_min_step", "> 0",
               coarse_min_step)
      .require(coarse_back_within > 0.0 && coarse_back_within <= min_distance, "coarse_back_within",
               "in (0, min_distance] tolerances", coarse_back_within)
      .nested("registration", registration.validate())
      .str();
}

RestartResult betterAlignmentElsewhere(const CoralPair& pair, const Eigen::Isometry3d& T_a_b,
                                       const JudgedPose& candidate,
                                       const ToleranceConfig& tolerance, const RestartConfig& cfg,
                                       const PoseJudge& judge) {
  RestartResult out;
  out.run = true;
  out.q_candidate = candidate.quality;
  const double q_candidate = candidate.quality;
  const SurfaceTarget target(pair.points(0), pair.config(), cfg.registration);
  // "Clearly lower": by a share of |Q| (Q may be slightly negative on clean walls).
  double best_q = q_candidate - (1.0 - cfg.max_q_ratio) * std::abs(q_candidate);
  const Eigen::Isometry3d T_b_a = T_a_b.inverse();
  auto tolerancesAway = [&](const Eigen::Isometry3d& T) {  // from the candidate's pose
    return toleranceSize(T_b_a * T, tolerance);
  };
  for (double radius : cfg.radii)
    for (int k = 0; k < cfg.directions; ++k) {
      const double angle = 2.0 * M_PI * k / cfg.directions;
      Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
      start.translation() =
          radius * tolerance.translation * Vec3(std::cos(angle), std::sin(angle), 0.0);
      ++out.starts;
      const Points& b = pair.points(1);
      Eigen::Isometry3d from = T_a_b * start;
      if (cfg.coarse_points > 0 && b.size() > cfg.coarse_points) {
        // Heading back: only for a start farther out than that (a nearer one starts there).
        const bool may_stop = radius > cfg.coarse_back_within;
        const RegistrationResult c = target.align(
            b, from, cfg.coarse_points, cfg.coarse_min_step, [&](const Eigen::Isometry3d& T) {
              return may_stop && tolerancesAway(T) < cfg.coarse_back_within;
            });
        if (!c.usable(cfg.registration)) continue;
        // Stopped ones too: coarse_back_within <= min_distance (validate()).
        if (tolerancesAway(c.T_a_b) < cfg.min_distance) {
          ++out.usable;  // back at the candidate's pose
          continue;
        }
        from = c.T_a_b;
      }
      const RegistrationResult r = target.align(b, from);
      if (!r.usable(cfg.registration)) continue;
      ++out.usable;
      const double distance = tolerancesAway(r.T_a_b);
      if (distance < cfg.min_distance) continue;  // back at the candidate's pose
      const JudgedPose w = judge(r.T_a_b);
      if (!w.accepted || !(w.quality < best_q) ||
          !(w.overlap >= cfg.min_overlap_ratio * candidate.overlap))
        continue;
      best_q = w.quality;
      out.better_elsewhere = true;
      out.T_a_b = r.T_a_b;
      out.distance = distance;
      out.q = w.quality;
    }
  return out;
}

NearbyAlignment registeredNearby(const CoralPair& pair, const Eigen::Isometry3d& T_a_b,
                                 const ToleranceConfig& tolerance, const RegistrationConfig& cfg,
                                 double max_size,
                                 const std::function<bool(const Eigen::Isometry3d&)>& accepts) {
  NearbyAlignment out;
  out.run = true;
  const SurfaceTarget target(pair.points(0), pair.config(), cfg);
  const RegistrationResult r = target.align(pair.points(1), T_a_b);
  if (!r.usable(cfg)) return out;
  out.usable = true;
  out.T_a_b = r.T_a_b;
  out.size = toleranceSize(T_a_b.inverse() * r.T_a_b, tolerance);
  out.accepted = out.size <= max_size && accepts(r.T_a_b);
  return out;
}

}  // namespace coral
}  // namespace coral_introspection
