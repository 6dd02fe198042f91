// Small priors of the odometry as Ceres costs with analytic Jacobians:
// - StatePrior: a Gaussian on one whole state (initialisation from the static start,
//   soft resets): r = W [p - p0; Log(q0^T q); v - v0; ba - ba0; bg - bg0].
// - ZeroVelocityFactor: v_i = 0 when the Doppler of the frame says the radar stands still.
// - GyroBiasFactor: b_g = mean gyro rate of an interval in which the IMU did not rotate.
#pragma once

#include <ceres/sized_cost_function.h>

#include "coral_introspection/rio/preintegration.hpp"

namespace coral_introspection {
namespace rio {

class StatePrior : public ceres::SizedCostFunction<15, 7, 9> {
 public:
  // sqrt_info: W with W^T W = covariance^-1 over [dp, dtheta, dv, dba, dbg].
  StatePrior(const NavState& mean, const Mat15& sqrt_info);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  NavState mean_;
  Mat15 sqrt_info_;
};

class ZeroVelocityFactor : public ceres::SizedCostFunction<3, 9> {
 public:
  explicit ZeroVelocityFactor(double sigma) : inv_sigma_(1.0 / sigma) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  double inv_sigma_;
};

class GyroBiasFactor : public ceres::SizedCostFunction<3, 9> {
 public:
  GyroBiasFactor(const Vec3& mean_rate, double sigma) : rate_(mean_rate), inv_sigma_(1.0 / sigma) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  Vec3 rate_;
  double inv_sigma_;
};

}  // namespace rio
}  // namespace coral_introspection
