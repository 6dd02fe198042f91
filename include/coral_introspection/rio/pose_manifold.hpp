// Ceres manifold of a pose block (p, q.x, q.y, q.z, q.w): tangent (dp, dtheta) with
// Plus(x, d) = (p + dp, q Exp(dtheta)). Cost functions of rio write their Jacobians with
// respect to the tangent into the first 6 of 7 columns (last column zero); PlusJacobian
// is therefore [I6; 0], so Ceres' J_ambient * PlusJacobian equals the tangent Jacobian.
#pragma once

#include <ceres/manifold.h>

namespace coral_introspection {
namespace rio {

class PoseManifold : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 7; }
  int TangentSize() const override { return 6; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

}  // namespace rio
}  // namespace coral_introspection
