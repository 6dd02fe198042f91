// Shared helpers of the rio tests: a smooth analytic trajectory with exact IMU readings,
// and a numeric (central difference, on the manifold) check of a cost's Jacobians.
#pragma once

#include <ceres/cost_function.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <vector>

#include "coral_introspection/rio/pose_manifold.hpp"
#include "coral_introspection/rio/radar_factors.hpp"
#include "coral_introspection/rio/types.hpp"

namespace rio_test {

using namespace coral_introspection::rio;

// p(t), phi(t) with R(t) = Exp(phi(t)); derivatives analytic.
struct Trajectory {
  double gravity = 9.81;
  Vec3 p(double t) const { return {std::sin(t), 0.5 * std::cos(2 * t), 0.3 * t}; }
  Vec3 v(double t) const { return {std::cos(t), -std::sin(2 * t), 0.3}; }
  Vec3 a(double t) const { return {-std::sin(t), -2 * std::cos(2 * t), 0.0}; }
  Vec3 phi(double t) const { return {0.3 * std::sin(t), 0.2 * std::cos(1.3 * t), 0.5 * t}; }
  Vec3 phiDot(double t) const { return {0.3 * std::cos(t), -0.26 * std::sin(1.3 * t), 0.5}; }
  Quat q(double t) const { return expQ(phi(t)); }
  // Body rate of R = Exp(phi): omega = Jr(phi) phi_dot.
  Vec3 omega(double t) const { return rightJacobian(phi(t)) * phiDot(t); }
  // Specific force in the body frame: R^T (a + g e_z).
  Vec3 specificForce(double t) const { return q(t).conjugate() * (a(t) + Vec3(0, 0, gravity)); }
  ImuSample imu(double t, const Vec3& ba = Vec3::Zero(), const Vec3& bg = Vec3::Zero()) const {
    return {t, specificForce(t) + ba, omega(t) + bg};
  }
  NavState state(double t, const Vec3& ba = Vec3::Zero(), const Vec3& bg = Vec3::Zero()) const {
    NavState s;
    s.t = t;
    s.p = p(t);
    s.q = q(t);
    s.v = v(t);
    s.ba = ba;
    s.bg = bg;
    return s;
  }
};

// A radar mounted turned and off the body origin (every axis of the Jacobians exercised).
inline Extrinsics testExtrinsics() {
  Extrinsics e;
  e.R = expQ(Vec3(0.3, -2.0, 0.8)).toRotationMatrix();
  e.t = Vec3(0.1, -0.05, 0.2);
  return e;
}

// Plus on a block of `size` doubles (7 = pose manifold, else Euclidean).
inline void plusBlock(const double* x, const double* d, double* out, int size) {
  if (size == 7) {
    PoseManifold().Plus(x, d, out);
  } else {
    for (int i = 0; i < size; ++i) out[i] = x[i] + d[i];
  }
}

// Compares the analytic tangent Jacobians of cost at `blocks` with central differences.
// Returns the largest absolute difference over all entries, relative to max(1, |J|).
inline double jacobianError(const ceres::CostFunction& cost, std::vector<double*> blocks,
                            double h = 1e-6) {
  const int nr = cost.num_residuals();
  const auto& sizes = cost.parameter_block_sizes();
  std::vector<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(
      blocks.size());
  std::vector<double*> jp;
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    J[k].resize(nr, sizes[k]);
    jp.push_back(J[k].data());
  }
  Eigen::VectorXd r0(nr);
  EXPECT_TRUE(cost.Evaluate(blocks.data(), r0.data(), jp.data()));
  double worst = 0.0;
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    const int size = sizes[k], tangent = size == 7 ? 6 : size;
    std::vector<double> orig(blocks[k], blocks[k] + size);
    for (int c = 0; c < tangent; ++c) {
      Eigen::VectorXd rp(nr), rm(nr), d = Eigen::VectorXd::Zero(tangent);
      d(c) = h;
      plusBlock(orig.data(), d.data(), blocks[k], size);
      cost.Evaluate(blocks.data(), rp.data(), nullptr);
      d(c) = -h;
      plusBlock(orig.data(), d.data(), blocks[k], size);
      cost.Evaluate(blocks.data(), rm.data(), nullptr);
      std::copy(orig.begin(), orig.end(), blocks[k]);
      const Eigen::VectorXd numeric = (rp - rm) / (2 * h);
      const Eigen::VectorXd analytic = J[k].col(c);
      const double scale = std::max(1.0, numeric.cwiseAbs().maxCoeff());
      worst = std::max(worst, (numeric - analytic).cwiseAbs().maxCoeff() / scale);
    }
    if (size == 7) {
      EXPECT_EQ(J[k].col(6).cwiseAbs().maxCoeff(), 0.0);  // lift convention
    }
  }
  return worst;
}

}  // namespace rio_test
