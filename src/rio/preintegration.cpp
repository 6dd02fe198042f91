#include "coral_introspection/rio/preintegration.hpp"

#include "coral_introspection/coral/validation.hpp"

#include <Eigen/Eigenvalues>

namespace coral_introspection {
namespace rio {

std::string ImuNoiseConfig::validate() const {
  return coral::Problems()
      .require(acc_noise > 0.0, "acc_noise", "> 0 m/s^2/sqrt(Hz)", acc_noise)
      .require(gyro_noise > 0.0, "gyro_noise", "> 0 rad/s/sqrt(Hz)", gyro_noise)
      .require(acc_bias_walk > 0.0, "acc_bias_walk", "> 0 m/s^3/sqrt(Hz)", acc_bias_walk)
      .require(gyro_bias_walk > 0.0, "gyro_bias_walk", "> 0 rad/s^2/sqrt(Hz)", gyro_bias_walk)
      .require(gravity > 9.0 && gravity < 10.5, "gravity", "in (9, 10.5) m/s^2", gravity)
      .str();
}

Preintegration::Preintegration(const ImuSample& first, const Vec3& ba, const Vec3& bg,
                               const ImuNoiseConfig& noise)
    : noise_(noise), samples_{first}, ba_(ba), bg_(bg) {
  reset();
}

Mat15 inverseSqrt15(const Mat15& S, double min_eigenvalue) {
  Eigen::SelfAdjointEigenSolver<Mat15> es(0.5 * (S + S.transpose()));
  const Vec15 lambda = es.eigenvalues().cwiseMax(min_eigenvalue);
  // W = Lambda^-1/2 U^T: W^T W = U Lambda^-1 U^T.
  return lambda.cwiseSqrt().cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
}

const Mat15& Preintegration::sqrtInformation() const {
  if (!sqrt_info_valid_) {
    sqrt_info_ = inverseSqrt15(covariance_, 1e-14);
    sqrt_info_valid_ = true;
  }
  return sqrt_info_;
}

void Preintegration::reset() {
  sqrt_info_valid_ = false;
  sum_dt_ = 0.0;
  delta_p_.setZero();
  delta_v_.setZero();
  delta_q_.setIdentity();
  jacobian_.setIdentity();
  covariance_.setZero();
}

void Preintegration::push(const ImuSample& s) {
  integrate(samples_.back(), s);
  samples_.push_back(s);
}

void Preintegration::repropagate(const Vec3& ba, const Vec3& bg) {
  ba_ = ba;
  bg_ = bg;
  reset();
  for (std::size_t k = 1; k < samples_.size(); ++k) integrate(samples_[k - 1], samples_[k]);
}

void Preintegration::integrate(const ImuSample& a, const ImuSample& b) {
  const double dt = b.t - a.t;
  if (!(dt > 0.0)) return;  // duplicate stamp: nothing to integrate
  // Mid-point rule: the rotation uses the mean rate, the velocity the mean of the two
  // accelerations rotated by the orientations at both ends.
  const Vec3 w = 0.5 * (a.gyro + b.gyro) - bg_;
  const Quat dq_step = expQ(w * dt);
  const Quat q1 = delta_q_ * dq_step;
  const Mat3 R0 = delta_q_.toRotationMatrix(), R1 = q1.toRotationMatrix();
  const Vec3 acc0 = a.acc - ba_, acc1 = b.acc - ba_;
  const Vec3 un_acc = 0.5 * (R0 * acc0 + R1 * acc1);
  const Vec3 p1 = delta_p_ + delta_v_ * dt + 0.5 * un_acc * dt * dt;
  const Vec3 v1 = delta_v_ + un_acc * dt;

  // Error-state transition F and noise input V (noise order: acc0, gyro0, acc1, gyro1,
  // acc bias walk, gyro bias walk). dtheta_1 = Exp(w dt)^T dtheta_0 - Jr(w dt) dt dbg.
  const Mat3 I = Mat3::Identity();
  const Mat3 a0x = skew(acc0), a1x = skew(acc1);
  const Mat3 Fqq = dq_step.toRotationMatrix().transpose();
  const Mat3 Fqbg = -rightJacobian(w * dt) * dt;
  Mat15 F = Mat15::Identity();
  F.block<3, 3>(kP, kR) = -0.25 * dt * dt * (R0 * a0x + R1 * a1x * Fqq);
  F.block<3, 3>(kP, kV) = I * dt;
  F.block<3, 3>(kP, kBa) = -0.25 * (R0 + R1) * dt * dt;
  F.block<3, 3>(kP, kBg) = -0.25 * dt * dt * R1 * a1x * Fqbg;
  F.block<3, 3>(kR, kR) = Fqq;
  F.block<3, 3>(kR, kBg) = Fqbg;
  F.block<3, 3>(kV, kR) = -0.5 * dt * (R0 * a0x + R1 * a1x * Fqq);
  F.block<3, 3>(kV, kBa) = -0.5 * (R0 + R1) * dt;
  F.block<3, 3>(kV, kBg) = -0.5 * dt * R1 * a1x * Fqbg;
  Eigen::Matrix<double, 15, 18> V = Eigen::Matrix<double, 15, 18>::Zero();
  V.block<3, 3>(kP, 0) = 0.25 * R0 * dt * dt;
  V.block<3, 3>(kP, 3) = -0.125 * R1 * a1x * dt * dt * dt;
  V.block<3, 3>(kP, 6) = 0.25 * R1 * dt * dt;
  V.block<3, 3>(kP, 9) = V.block<3, 3>(kP, 3);
  V.block<3, 3>(kR, 3) = 0.5 * I * dt;
  V.block<3, 3>(kR, 9) = 0.5 * I * dt;
  V.block<3, 3>(kV, 0) = 0.5 * R0 * dt;
  V.block<3, 3>(kV, 3) = -0.25 * R1 * a1x * dt * dt;
  V.block<3, 3>(kV, 6) = 0.5 * R1 * dt;
  V.block<3, 3>(kV, 9) = V.block<3, 3>(kV, 3);
  V.block<3, 3>(kBa, 12) = I * dt;
  V.block<3, 3>(kBg, 15) = I * dt;
  // Discrete variances from the densities (see ImuNoiseConfig). Each sample enters two
  // consecutive mid-point steps with weight 1/2; treating the two samples of a step as
  // independent, each with variance 2 density^2 / dt, gives the continuous-time variance
  // density^2 * T over the interval (checked against Monte Carlo in the tests).
  Eigen::Matrix<double, 18, 1> q;
  const double na = 2.0 * noise_.acc_noise * noise_.acc_noise / dt;
  const double ng = 2.0 * noise_.gyro_noise * noise_.gyro_noise / dt;
  const double nba = noise_.acc_bias_walk * noise_.acc_bias_walk / dt;
  const double nbg = noise_.gyro_bias_walk * noise_.gyro_bias_walk / dt;
  q << na, na, na, ng, ng, ng, na, na, na, ng, ng, ng, nba, nba, nba, nbg, nbg, nbg;

  sqrt_info_valid_ = false;
  jacobian_ = F * jacobian_;
  covariance_ = F * covariance_ * F.transpose() + V * q.asDiagonal() * V.transpose();
  delta_p_ = p1;
  delta_v_ = v1;
  delta_q_ = q1.normalized();
  sum_dt_ += dt;
}

void Preintegration::corrected(const Vec3& ba, const Vec3& bg, Vec3* dp, Quat* dq, Vec3* dv) const {
  const Vec3 dba = ba - ba_, dbg = bg - bg_;
  *dp = delta_p_ + jacobian_.block<3, 3>(kP, kBa) * dba + jacobian_.block<3, 3>(kP, kBg) * dbg;
  *dq = delta_q_ * expQ(jacobian_.block<3, 3>(kR, kBg) * dbg);
  *dv = delta_v_ + jacobian_.block<3, 3>(kV, kBa) * dba + jacobian_.block<3, 3>(kV, kBg) * dbg;
}

Vec15 Preintegration::residual(const NavState& i, const NavState& j) const {
  Vec3 dp, dv;
  Quat dq;
  corrected(i.ba, i.bg, &dp, &dq, &dv);
  const Vec3 g(0.0, 0.0, noise_.gravity);
  const double T = sum_dt_;
  const Mat3 RiT = i.q.toRotationMatrix().transpose();
  Vec15 r;
  r.segment<3>(kP) = RiT * (j.p - i.p - i.v * T + 0.5 * g * T * T) - dp;
  r.segment<3>(kR) = logQ(dq.conjugate() * i.q.conjugate() * j.q);
  r.segment<3>(kV) = RiT * (j.v - i.v + g * T) - dv;
  r.segment<3>(kBa) = j.ba - i.ba;
  r.segment<3>(kBg) = j.bg - i.bg;
  return r;
}

NavState Preintegration::predict(const NavState& i) const {
  Vec3 dp, dv;
  Quat dq;
  corrected(i.ba, i.bg, &dp, &dq, &dv);
  const Vec3 g(0.0, 0.0, noise_.gravity);
  const double T = sum_dt_;
  NavState j = i;
  j.t = samples_.back().t;
  j.p = i.p + i.v * T - 0.5 * g * T * T + i.q * dp;
  j.v = i.v - g * T + i.q * dv;
  j.q = (i.q * dq).normalized();
  return j;
}

}  // namespace rio
}  // namespace coral_introspection
