#include "coral_introspection/coral/restart_check.hpp"

#include <cmath>
#include <memory>

#include "coral_introspection/coral/refinement.hpp"
#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace coral {

std::string RestartConfig::validateStarts() const {
  bool radii_ok = !radii.empty() && radii.size() <= 8;
  for (double r : radii) radii_ok = radii_ok && r > 0.0 && r <= 100.0;
  return Problems()
      .require(radii_ok, "radii", "1-8 entries, each in (0, 100] tolerances", radii.size())
      .require(directions >= 1 && directions <= 64, "directions", "in [1, 64]", directions)
      .require(min_distance > 0.0, "min_distance", "> 0 tolerances", min_distance)
      .require(max_q_ratio > 0.0 && max_q_ratio <= 1.0, "max_q_ratio", "in (0, 1]", max_q_ratio)
      .require(min_overlap_ratio >= 0.0 && min_overlap_ratio <= 1.0, "min_overlap_ratio",
               "in [0, 1]", min_overlap_ratio)
      .require(std::isfinite(coarse_min_step) && coarse_min_step > 0.0, "coarse_min_step", "> 0",
               coarse_min_step)
      .require(coarse_back_within > 0.0 && coarse_back_within <= min_distance, "coarse_back_within",
               "in (0, min_distance] tolerances", coarse_back_within)
      .require(coarse_same_within >= 0.0 && coarse_same_within <= coarse_back_within,
               "coarse_same_within", "in [0, coarse_back_within] tolerances", coarse_same_within)
      .str();
}

std::string RestartConfig::validate() const {
  const std::string starts = validateStarts();
  return Problems()
      .require(starts.empty(), starts)
      .nested("registration", registration.validate())
      .str();
}

namespace {
// The shared target, or one built into *own from a's filtered points.
const SurfaceTarget& targetOf(const CoralPair& pair, const RegistrationConfig& cfg,
                              const SurfaceTarget* shared, std::unique_ptr<SurfaceTarget>* own) {
  if (shared != nullptr) return *shared;
  own->reset(new SurfaceTarget(pair.points(0), pair.config(), cfg));
  return **own;
}

// The size [tolerances] of a pose's difference from `from` (toleranceSize): how far a
// registration has moved the candidate's pose.
struct TolerancesFrom {
  TolerancesFrom(const Eigen::Isometry3d& from, const ToleranceConfig& tolerance)
      : inverse(from.inverse()), tolerance(tolerance) {}
  double operator()(const Eigen::Isometry3d& T) const {
    return toleranceSize(inverse * T, tolerance);
  }
  Eigen::Isometry3d inverse;
  const ToleranceConfig& tolerance;
};

// A pose with Q below best_q and at least min_overlap_ratio of the candidate's overlap.
bool lowerWithOverlap(double quality, double overlap, double best_q, const JudgedPose& candidate,
                      const RestartConfig& cfg) {
  return quality < best_q && overlap >= cfg.min_overlap_ratio * candidate.overlap;
}
}  // namespace

RestartResult betterAlignmentElsewhere(const CoralPair& pair, const Eigen::Isometry3d& T_a_b,
                                       const JudgedPose& candidate,
                                       const ToleranceConfig& tolerance, const RestartConfig& cfg,
                                       const PoseJudge& judge, const SurfaceTarget* shared) {
  RestartResult out;
  out.run = true;
  out.q_candidate = candidate.quality;
  const double q_candidate = candidate.quality;
  std::unique_ptr<SurfaceTarget> own;
  const SurfaceTarget& target = targetOf(pair, cfg.registration, shared, &own);
  // "Clearly lower": by a share of |Q| (Q may be slightly negative on clean walls).
  double best_q = q_candidate - (1.0 - cfg.max_q_ratio) * std::abs(q_candidate);
  const TolerancesFrom tolerancesAway(T_a_b, tolerance);  // from the candidate's pose
  struct Refined {  // a start registered with all points: where it started, usable
    Eigen::Isometry3d coarse_end;
    bool usable;
  };
  std::vector<Refined> refined;
  auto earlier = [&](const Eigen::Isometry3d& T) -> const Refined* {  // within coarse_same_within
    for (const Refined& e : refined)
      if (TolerancesFrom(e.coarse_end, tolerance)(T) < cfg.coarse_same_within) return &e;
    return nullptr;
  };
  // Heading back: within coarse_back_within of the candidate's pose. Ends the coarse phase and
  // the full registration after it: the start is then back at the candidate (below), and the
  // last iterations into a minimum cost most (a start that settled 2-3 tolerances away
  // converged back in 33-38 iterations of all points, 0.04-0.05 s: doc/loop_closure.md "The
  // cost of a rejection").
  const std::function<bool(const Eigen::Isometry3d&)> back_at_candidate =
      [&](const Eigen::Isometry3d& T) { return tolerancesAway(T) < cfg.coarse_back_within; };
  const std::function<bool(const Eigen::Isometry3d&)> no_stop;
  for (double radius : cfg.radii)
    for (int k = 0; k < cfg.directions; ++k) {
      const double angle = 2.0 * M_PI * k / cfg.directions;
      Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
      start.translation() =
          radius * tolerance.translation * Vec3(std::cos(angle), std::sin(angle), 0.0);
      ++out.starts;
      const Points& b = pair.points(1);
      Eigen::Isometry3d from = T_a_b * start;
      const bool dense = cfg.coarse_points > 0 && b.size() > cfg.coarse_points;
      if (dense) {
        // Heading back: only for a start farther out than that (a nearer one starts there).
        const bool may_stop = radius > cfg.coarse_back_within;
        const RegistrationResult c = target.align(
            b, from, cfg.coarse_points, cfg.coarse_min_step, [&](const Eigen::Isometry3d& T) {
              return (may_stop && back_at_candidate(T)) || earlier(T) != nullptr;
            });
        if (!c.usable(cfg.registration)) continue;
        // Stopped ones too: coarse_back_within <= min_distance (validate()).
        if (tolerancesAway(c.T_a_b) < cfg.min_distance) {
          ++out.usable;  // back at the candidate's pose
          ++out.back;
          continue;
        }
        // At (or on its way through) the pose where an earlier start's coarse registration
        // ended: the full one would end where that one's did (all the starts that end away,
        // on both Livox candidates the check rejects, end within 0.03 tolerances of each
        // other; 0.03-0.05 s each).
        if (const Refined* same = earlier(c.T_a_b)) {
          ++out.merged;
          out.usable += same->usable ? 1 : 0;
          continue;
        }
        from = c.T_a_b;
      }
      const RegistrationResult r = target.align(b, from, SurfaceTarget::kMaxSourcePoints, 0.0,
                                                dense ? back_at_candidate : no_stop);
      out.returned += r.stopped ? 1 : 0;
      refined.push_back({from, r.usable(cfg.registration)});
      if (!r.usable(cfg.registration)) continue;
      ++out.usable;
      const double distance = tolerancesAway(r.T_a_b);
      if (distance < cfg.min_distance) {  // back at the candidate's pose
        ++out.back;
        continue;
      }
      // Q (Eq. 5) and the overlap first, one CorAl evaluation: the judge's other terms cost a
      // dozen more (the relative check's poses), and only a lower Q with the overlap can count.
      const CoralResult at = pair.evaluate(r.T_a_b, nullptr, false);
      if (!lowerWithOverlap(at.quality, at.overlap, best_q, candidate, cfg)) continue;
      const JudgedPose w = judge(r.T_a_b);
      if (!w.accepted || !lowerWithOverlap(w.quality, w.overlap, best_q, candidate, cfg)) continue;
      best_q = w.quality;
      out.better_elsewhere = true;
      out.T_a_b = r.T_a_b;
      out.distance = distance;
      out.q = w.quality;
    }
  return out;
}

NearbyAlignment registeredNearby(const CoralPair& pair, const Eigen::Isometry3d& T_a_b,
                                 const ToleranceConfig& tolerance, const RestartConfig& restart,
                                 double max_size,
                                 const std::function<bool(const Eigen::Isometry3d&)>& accepts,
                                 const SurfaceTarget* shared) {
  NearbyAlignment out;
  out.run = true;
  const RegistrationConfig& cfg = restart.registration;
  std::unique_ptr<SurfaceTarget> own;
  const SurfaceTarget& target = targetOf(pair, cfg, shared, &own);
  const Points& b = pair.points(1);
  const TolerancesFrom size(T_a_b, tolerance);
  // The screen, for dense scans: a candidate far from any alignment (a look-alike place, a
  // pose metres off) runs away from its pose, and 50 iterations of the full registration of a
  // 64-beam scan cost 0.1 s (doc/loop_closure.md "The cost of a rejection"). A registration
  // that moves the pose a tolerance or more has left the tolerance around it (max_size < 1,
  // GateConfig::validate) and is ended there. Coarse first (the restart check's coarse phase),
  // then the full registration from the given pose (not the coarse end: one that stays within
  // a tolerance ends exactly where it ends without the screen), stopped the same way: the
  // coarse one can settle near the pose where the full one slides away (a candidate turned by
  // 15 deg).
  const bool screen =
      restart.coarse_points > 0 && b.size() > restart.coarse_points && max_size < 1.0;
  std::function<bool(const Eigen::Isometry3d&)> away;
  if (screen) away = [&](const Eigen::Isometry3d& T) { return size(T) >= 1.0; };
  auto screened = [&](const RegistrationResult& r) {
    out.usable = out.screened = true;
    out.T_a_b = r.T_a_b;
    out.size = size(r.T_a_b);
    return out;
  };
  if (screen) {
    const RegistrationResult c =
        target.align(b, T_a_b, restart.coarse_points, restart.coarse_min_step, away);
    if (c.usable(cfg) && away(c.T_a_b)) return screened(c);
  }
  const RegistrationResult r = target.align(b, T_a_b, SurfaceTarget::kMaxSourcePoints, 0.0, away);
  if (!r.usable(cfg)) return out;
  if (r.stopped) return screened(r);
  out.usable = true;
  out.T_a_b = r.T_a_b;
  out.size = size(r.T_a_b);
  out.accepted = out.size <= max_size && accepts(r.T_a_b);
  return out;
}

}  // namespace coral
}  // namespace coral_introspection
