// A small point-to-line (2D) / point-to-plane (3D) ICP on the points a CoralPair already
// filtered: the registration behind the loop verdict's restart check (restart_check.hpp).
// The verdict itself never registers; a loop candidate arrives registered by the back end's
// own matcher. The check registers it again from other starts to learn whether a better
// alignment lies a metre or more away (a registration that stopped off the revisit along
// repeated structure). Gauss-Newton on n . (T p - q) for each point p of b and the nearest
// point q of a (normal n from q's own neighbourhood, as in constraint.hpp; Cauchy weights),
// the linearised point-to-plane ICP of Chen and Medioni (1992) as ROS's laser_scan_matcher
// (PL-ICP) and PCL's point-to-plane ICP use it. ROS-free, no exceptions.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace coral {

struct RegistrationConfig {
  // [m] a point of b farther than this from every point of a has no correspondence
  // (coral_loop_eval's PCL registrations use the same 1.5 m).
  double max_correspondence = 1.5;
  int max_iterations = 50;
  // [m and rad] converged once an update moves the pose by less than this in translation and
  // in rotation.
  double min_step = 1e-5;
  int min_correspondences = 10;  // fewer at any iteration: no result
  // [m] radius of the neighbourhood a target point's normal is estimated from; 0 = CorAl's
  // (CoralConfig::maxRadius()). A spinning lidar's rings lie further apart than CorAl's radius
  // at range: its patches need a larger one to span two rings (3D points whose neighbourhood
  // is a line get no normal).
  double normal_radius = 0.0;
  // [m] Cauchy scale of the residuals (0 = plain least squares). Loop candidates share part
  // of their structure only; unweighted, what one scan sees and the other does not pulls
  // the optimum centimetres to decimetres off the revisit's (measured on the ACES and Intel
  // relations: plain least squares came back 0.1-0.35 m from poses PCL's ICP had reached,
  // at higher Q). A third of the 2D presets' 0.3 m translation tolerance; 0.05-0.2 m gave
  // the same restart-check results there.
  double robust_scale = 0.1;
  std::string validate() const;  // empty when valid
};

struct RegistrationResult {
  Eigen::Isometry3d T_a_b = Eigen::Isometry3d::Identity();  // b's points into a's frame
  bool converged = false;  // the last update moved less than min_step
  bool stopped = false;    // align's `stop` ended it
  int iterations = 0;
  int correspondences = 0;  // at the last iteration
  // A pose to judge: max_iterations ran out or the update became small, with at least
  // min_correspondences correspondences. An ICP that alternates between two correspondence
  // sets near a minimum ends there too (PCL counts reaching max_iterations as converged).
  bool usable(const RegistrationConfig& cfg) const {
    return correspondences >= cfg.min_correspondences;
  }
};

// Scan a (its own frame) prepared once as the target of many registrations: the points whose
// neighbourhood within cfg.normal_radius (0: coral.maxRadius()) holds coral.min_neighbours
// points and is a line (2D) or a plane spread in two directions (3D), with their normals.
// Non-finite points are skipped. At most kMaxTargetPoints points of a (a deterministic stride)
// get a normal, each from all of a's points around it: point-to-plane residuals do not need
// every point of a plane, and the normals are most of a dense 3D target's cost (a 64-beam
// scan's 13k filtered points: about 30 -> 13 ms; 2D scans stay whole).
class SurfaceTarget {
 public:
  // Preconditions: coral.validate() and cfg.validate() are empty.
  SurfaceTarget(const Points& a, const CoralConfig& coral, const RegistrationConfig& cfg);
  ~SurfaceTarget();
  SurfaceTarget(const SurfaceTarget&) = delete;
  SurfaceTarget& operator=(const SurfaceTarget&) = delete;

  std::size_t size() const;  // target points with a normal
  // Registers b (its own frame) onto the target from T_init. dimension 2: x, y, yaw (z, roll
  // and pitch of T_init kept); 3: 6 DoF. At most max_points points of b are used (a
  // deterministic stride); converged once an update moves less than min_step (0: the
  // config's). `stop`, when given, sees the pose after each update and ends the registration
  // there when it returns true (RegistrationResult::stopped). Never throws.
  RegistrationResult align(const Points& b, const Eigen::Isometry3d& T_init,
                           std::size_t max_points = kMaxSourcePoints, double min_step = 0.0,
                           const std::function<bool(const Eigen::Isometry3d&)>& stop = {}) const;
  static constexpr std::size_t kMaxSourcePoints = 2000;
  static constexpr std::size_t kMaxTargetPoints = 6000;  // points of a given a normal

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// A SurfaceTarget built on first use: the checks of one verdict that register (the coarse
// probe's registration from the pose, the restart check, the registration of a rejected loop
// candidate) share one target instead of building it each (a 64-beam scan's: ~13 ms). The
// points and configs must outlive it. Not for concurrent use.
class LazySurfaceTarget {
 public:
  LazySurfaceTarget(const Points& a, const CoralConfig& coral, const RegistrationConfig& cfg)
      : a_(a), coral_(coral), cfg_(cfg) {}
  const RegistrationConfig& config() const { return cfg_; }
  const SurfaceTarget& get() const {
    if (!target_) target_ = std::make_unique<SurfaceTarget>(a_, coral_, cfg_);
    return *target_;
  }

 private:
  const Points& a_;
  const CoralConfig& coral_;
  const RegistrationConfig& cfg_;
  mutable std::unique_ptr<SurfaceTarget> target_;
};

}  // namespace coral
}  // namespace coral_introspection
