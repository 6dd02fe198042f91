// IMU preintegration between two radar frames (the r_I term of Eq. 2, formulated as in
// the authors' system and VINS-Mono): mid-point integration of the deltas
// (alpha = delta p, gamma = delta q, beta = delta v) in the body frame of frame i, their
// 15x15 Jacobian with respect to the error state [dp, dtheta, dv, dba, dbg] (for the
// first-order bias correction) and the 15x15 covariance propagated from the noise
// densities. Orientation errors are right perturbations: q <- q Exp(dtheta).
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/rio/types.hpp"

namespace coral_introspection {
namespace rio {

using Mat15 = Eigen::Matrix<double, 15, 15>;
using Vec15 = Eigen::Matrix<double, 15, 1>;

// Continuous-time noise densities of the IMU (the discrete variance of one sample of
// period dt is density^2 / dt; a bias random walk adds walk^2 * dt per step).
struct ImuNoiseConfig {
  double acc_noise = 0.02;         // [m/s^2/sqrt(Hz)] accelerometer white noise
  double gyro_noise = 0.002;       // [rad/s/sqrt(Hz)] gyroscope white noise
  double acc_bias_walk = 0.001;    // [m/s^3/sqrt(Hz)] accelerometer bias random walk
  double gyro_bias_walk = 0.0001;  // [rad/s^2/sqrt(Hz)] gyroscope bias random walk
  double gravity = 9.81;           // [m/s^2] magnitude; world z points up
  std::string validate() const;    // empty when valid
};

// Indices of the error-state blocks.
enum : int { kP = 0, kR = 3, kV = 6, kBa = 9, kBg = 12 };

class Preintegration {
 public:
  // Starts at sample `first` (its time is t_i) with the bias linearisation point (ba, bg).
  Preintegration(const ImuSample& first, const Vec3& ba, const Vec3& bg,
                 const ImuNoiseConfig& noise);

  // Integrates from the last sample to s (mid-point rule); s.t must not be earlier.
  void push(const ImuSample& s);
  // Integrates all samples again with a new bias linearisation point.
  void repropagate(const Vec3& ba, const Vec3& bg);

  // Bias-corrected deltas for biases (ba, bg): first order around the linearisation point.
  void corrected(const Vec3& ba, const Vec3& bg, Vec3* dp, Quat* dq, Vec3* dv) const;

  // Unwhitened residual of states i (start) and j (end):
  //   r_p = R_i^T (p_j - p_i - v_i dt + g dt^2 / 2) - dp,  r_q = Log(dq^T R_i^T R_j),
  //   r_v = R_i^T (v_j - v_i + g dt) - dv,  r_ba = ba_j - ba_i,  r_bg = bg_j - bg_i
  // with g = (0, 0, gravity) and the bias-corrected deltas evaluated at state i's biases.
  Vec15 residual(const NavState& i, const NavState& j) const;

  // State j predicted from state i (biases of i kept).
  NavState predict(const NavState& i) const;

  double dt() const { return sum_dt_; }
  const Vec3& deltaP() const { return delta_p_; }
  const Quat& deltaQ() const { return delta_q_; }
  const Vec3& deltaV() const { return delta_v_; }
  const Vec3& linearizedBa() const { return ba_; }
  const Vec3& linearizedBg() const { return bg_; }
  const Mat15& jacobian() const { return jacobian_; }
  const Mat15& covariance() const { return covariance_; }
  // W with W^T W = covariance^-1 (computed once per integration, cached).
  const Mat15& sqrtInformation() const;
  double gravity() const { return noise_.gravity; }
  const std::vector<ImuSample>& samples() const { return samples_; }

 private:
  void reset();
  void integrate(const ImuSample& a, const ImuSample& b);

  ImuNoiseConfig noise_;
  std::vector<ImuSample> samples_;
  Vec3 ba_, bg_;
  double sum_dt_ = 0.0;
  Vec3 delta_p_, delta_v_;
  Quat delta_q_;
  Mat15 jacobian_, covariance_;
  mutable Mat15 sqrt_info_;
  mutable bool sqrt_info_valid_ = false;
};

// W with W^T W = S^-1 for a symmetric positive (semi-)definite S (eigenvalues floored at
// min_eigenvalue first so a rank-deficient S stays usable).
Mat15 inverseSqrt15(const Mat15& S, double min_eigenvalue);

}  // namespace rio
}  // namespace coral_introspection
