// Induced misalignments for self-supervised training (paper Sec. III-F, IV, V): the later
// scan b of a pair is displaced in its own sensor frame, T_a_b' = T_a_b * Delta.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace coral_introspection {
namespace eval {

struct PerturbationConfig {
  // Sec. V radar protocol: 4 translations per pair (forward +x, backward -x, left +y,
  // right -y of b's sensor frame) at each magnitude [m].
  std::vector<double> translations = {0.3, 0.5, 0.7};
  // Pure yaw offsets +-theta about b's vertical axis, one group per magnitude [rad]
  // (Sec. V-C orientation errors). Empty by default for radar.
  std::vector<double> rotations;
  // Sec. IV lidar protocol: every translation offset is combined with a yaw of this
  // magnitude [rad], alternating sign (forward/left +, backward/right -). 0 = pure
  // translations. lidarProtocol() sets 0.1 m + 0.1 rad.
  double combined_yaw = 0.0;

  static PerturbationConfig radarProtocol();  // 0.3, 0.5, 0.7 m
  static PerturbationConfig lidarProtocol();  // 0.1 m + 0.1 rad
  std::string validate() const;               // empty when valid
};

struct Perturbation {
  std::string name;                       // e.g. "forward", "left", "yaw+"
  std::string group;                      // error-magnitude label of the report row, e.g. "0.3 m"
  double dx = 0.0, dy = 0.0, dyaw = 0.0;  // offset in b's sensor frame [m, m, rad]
  Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();  // Delta = se2(dx, dy, dyaw)
};

// Every misalignment of the protocol, grouped by magnitude (translations, then rotations).
std::vector<Perturbation> makePerturbations(const PerturbationConfig& cfg);

// T_a_b' = T_a_b * Delta: b's sensor pose moved by Delta expressed in b's own frame.
Eigen::Isometry3d perturb(const Eigen::Isometry3d& T_a_b, const Perturbation& p);

// Label used for a group: "0.3 m", "0.1 m + 0.1 rad", "0.05 rad".
std::string groupLabel(double translation_m, double yaw_rad);

}  // namespace eval
}  // namespace coral_introspection
