// Radar residuals of the odometry as Ceres costs with analytic Jacobians.
//
// Doppler (Sec. III-C, Eq. 9): a static point seen along the unit bearing d (radar frame)
// with sign-normalised Doppler m (= d^T v_radar expected, i.e. minus the radial velocity
// when that is positive away from the sensor):
//   r_D = w (d^T R_E^T (R_i^T v_i + (omega - b_g)^ t_E) - m),
// omega the gyro rate at the frame time, (R_E, t_E) the radar pose in the body frame and
// w = 1 / sqrt(variance) from the point's bearing uncertainty (Eq. 10-12).
//
// Point to landmark (Sec. III-E, Eq. 15-18): the residual is expressed in the radar frame,
// where the polar covariance Sigma_k lives, and whitened there:
//   r_P = W_k (R_E^T (R_i^T (l - p_i) - t_E) - p_k),  W_k^T W_k = Sigma_k^-1.
// Its squared norm equals the paper's world-frame residual whitened by
// R_i R_E Sigma_k R_E^T R_i^T (Eq. 18), without approximating that rotation.
#pragma once

#include <ceres/sized_cost_function.h>

#include "coral_introspection/rio/so3.hpp"

namespace coral_introspection {
namespace rio {

// Radar pose in the body (IMU) frame: p_body = R_E p_radar + t_E.
struct Extrinsics {
  Mat3 R = Mat3::Identity();
  Vec3 t = Vec3::Zero();
};

class DopplerFactor : public ceres::SizedCostFunction<1, 7, 9> {
 public:
  DopplerFactor(const Vec3& bearing, double m, const Vec3& omega, const Extrinsics& ext,
                double weight);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  Vec3 dE_;  // R_E d: the bearing in the body frame
  double m_;
  Vec3 omega_;
  Vec3 t_E_;
  double w_;
};

class PointFactor : public ceres::SizedCostFunction<3, 7, 3> {
 public:
  // p: the measured point (radar frame); W: whitening matrix of its covariance.
  PointFactor(const Vec3& p, const Mat3& W, const Extrinsics& ext);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  Vec3 Wp_;     // W p_k
  Mat3 W_RET_;  // W R_E^T
  Vec3 t_E_;
};

// W = Lambda^-1/2 U^T for S = U Lambda U^T, eigenvalues floored at min_eigenvalue.
Mat3 whitening3(const Mat3& S, double min_eigenvalue);

}  // namespace rio
}  // namespace coral_introspection
