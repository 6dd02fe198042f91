// The IMU term r_I(x_i, x_j) of Eq. 2 as a Ceres cost: the preintegration residual
// (Preintegration::residual) whitened by the inverse square root of its covariance, with
// analytic Jacobians with respect to (pose_i, speed_bias_i, pose_j, speed_bias_j).
#pragma once

#include <ceres/sized_cost_function.h>

#include "coral_introspection/rio/preintegration.hpp"

namespace coral_introspection {
namespace rio {

class ImuFactor : public ceres::SizedCostFunction<15, 7, 9, 7, 9> {
 public:
  // pre must outlive the factor (its cached square-root information whitens r).
  explicit ImuFactor(const Preintegration* pre) : pre_(pre) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  const Preintegration* pre_;
};

}  // namespace rio
}  // namespace coral_introspection
