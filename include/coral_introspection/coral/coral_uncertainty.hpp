// Uncertainty-aware CorAl: each point's neighbourhood is an ellipsoid that follows its
// measurement covariance (radar polar model, Eq. 3-8 of radar_point_uncertainty_slam)
// instead of one sphere. Semi-axis i along eigenvector v_i of Sigma_k is
//   a_i = clamp(gate_sigma * sqrt(lambda_i), r_min, r_max),
// so a radar point far away gets a neighbourhood stretched across the beam and short
// along it. With an isotropic Sigma_k = (d sin(alpha) / gate_sigma)^2 I this is exactly
// CorAl's dynamic radius r = d sin(alpha) clamped to [r_min, r_max] (Sec. III-C (2)).
#pragma once

#include <string>

#include "coral_introspection/coral/coral.hpp"

namespace coral_introspection {
namespace coral {

struct UncertainCoralConfig {
  // Entropy, overlap, E_reject, aggregation and dimension settings as in plain CorAl;
  // base.r_min / base.r_max bound the semi-axes (whatever base.dynamic_radius says).
  CoralConfig base;
  double gate_sigma = 3.0;       // semi-axes at gate_sigma standard deviations
  std::string validate() const;  // empty when valid
};

// CorAl (Eq. 2-6) with covariance-shaped neighbourhoods. Scan::covariances (same frame as
// the points, e.g. attachCovariances then transformScan) gives each point's shape; a scan
// without covariances, or a point with a non-finite one, uses the isotropic
// dynamicRadius(base, distance to its origin). PointEntropy::radius holds the largest
// semi-axis. Never throws; precondition: cfg.validate() is empty.
CoralResult computeCoralUncertain(const Scan& a, const Scan& b, const UncertainCoralConfig& cfg);

}  // namespace coral
}  // namespace coral_introspection
