// The polar point-uncertainty model (Sec. III-B) as the odometry uses it, including the
// ablations of Table I and the scaling of Table II: covariance of a radar point in the
// radar frame and variance of its Doppler residual.
#pragma once

#include "coral_introspection/rio/config.hpp"

namespace coral_introspection {
namespace rio {

// Sigma_k of the point p (radar frame, sensor at the origin) under cfg.mode, times
// cfg.covariance_scale:
//   kFull:      A diag(sigma_r^2, sigma_theta^2, sigma_phi^2) A^T       (Eq. 8)
//   kNone:      sigma_iso^2 I (residuals fused "without weighting", Sec. III-C, up to the
//               scale sigma_iso; the gate becomes Euclidean nearest neighbour)
//   kNoRange:   Eq. 8 with sigma_r -> shrink sigma_r (the paper's ablation, Sec. IV-B), or
//               with ablation_replace: sigma_iso^2 d d^T + (bearing part of Eq. 8)
//   kNoBearing: Eq. 8 with Sigma_Omega -> shrink^2 Sigma_Omega, or with ablation_replace:
//               sigma_r^2 d d^T + sigma_iso^2 (I - d d^T)
// The eigenvalue floor min_variance applies where Sigma_k is inverted.
Mat3 pointCovariance(const Vec3& p, const UncertaintyConfig& cfg);

// Variance of the Doppler residual (Eq. 9) of a static point p for the radar velocity
// v_radar: sigma_doppler^2 + J Sigma_k J^T (Eq. 10-12) with Sigma_k from pointCovariance,
// or the constant doppler_sigma_isotropic^2 in mode kNone. Range noise does not move the
// bearing, so kNoRange keeps the full Doppler weight; the paper's kNoBearing leaves only
// sigma_doppler (a constant weight).
double dopplerVariance(const Vec3& p, const Vec3& v_radar, const UncertaintyConfig& cfg);

}  // namespace rio
}  // namespace coral_introspection
