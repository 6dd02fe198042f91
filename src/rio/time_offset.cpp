#include "coral_introspection/rio/time_offset.hpp"

#include <cmath>
#include <vector>

#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace rio {

std::string TimeOffsetConfig::validate() const {
  return coral::Problems()
      .require(sigma > 0.0, "sigma", "> 0 s", sigma)
      .require(max_abs > 0.0 && max_abs < 1.0, "max_abs", "in (0, 1) s", max_abs)
      .require(max_time_at_bound > 0.0, "max_time_at_bound", "> 0 s", max_time_at_bound)
      .require(max_latency >= 0.0, "max_latency", ">= 0 s", max_latency)
      .str();
}

Vec3 staticPointRate(const Vec3& p, const Vec3& omega_radar, const Vec3& v_radar) {
  // p = R_r^T (l - p_r): dR_r^T/dt = -[omega_r]^ R_r^T, dp_r/dt = R_r v_r.
  return -(omega_radar.cross(p) + v_radar);
}

Vec3 radarAcceleration(const NavState& s, const Vec3& omega, const Vec3& alpha, const Vec3& f,
                       const Extrinsics& ext, double gravity) {
  // v_r = R_E^T (R^T v + (omega - b_g) x t_E) (Eq. 9's K); d(R^T v)/dt = R^T a - w x R^T v
  // with R^T a = f - b_a + R^T g (IMU model of the preintegration).
  const Vec3 w = omega - s.bg, v_body = s.q.conjugate() * s.v;
  const Vec3 acc_body = f - s.ba + s.q.conjugate() * Vec3(0.0, 0.0, -gravity);
  return ext.R.transpose() * (acc_body - w.cross(v_body) + alpha.cross(ext.t));
}

Vec3 angularAcceleration(const std::vector<ImuSample>& interval, double span) {
  if (interval.empty()) return Vec3::Zero();
  const double t_end = interval.back().t;
  double n = 0.0, st = 0.0, stt = 0.0;
  Vec3 sw = Vec3::Zero(), stw = Vec3::Zero();
  for (const ImuSample& s : interval) {
    if (s.t < t_end - span) continue;
    const double t = s.t - t_end;
    n += 1.0, st += t, stt += t * t, sw += s.gyro, stw += t * s.gyro;
  }
  const double den = n * stt - st * st;
  if (n < 3.0 || den <= 0.0) return Vec3::Zero();
  return (n * stw - st * sw) / den;
}

TimeShiftedFactor::TimeShiftedFactor(std::shared_ptr<const ceres::CostFunction> base,
                                     const Eigen::VectorXd& rate, double td_ref)
    : base_(std::move(base)), rate_(rate), td_ref_(td_ref) {
  set_num_residuals(base_->num_residuals());
  *mutable_parameter_block_sizes() = base_->parameter_block_sizes();
  mutable_parameter_block_sizes()->push_back(1);
}

bool TimeShiftedFactor::Evaluate(double const* const* parameters, double* residuals,
                                 double** jacobians) const {
  const std::size_t n_base = base_->parameter_block_sizes().size();
  if (!base_->Evaluate(parameters, residuals, jacobians)) return false;
  const double shift = parameters[n_base][0] - td_ref_;
  Eigen::Map<Eigen::VectorXd>(residuals, rate_.size()) += shift * rate_;
  if (jacobians != nullptr && jacobians[n_base] != nullptr)
    Eigen::Map<Eigen::VectorXd>(jacobians[n_base], rate_.size()) = rate_;
  return true;
}

bool TimeOffsetPrior::Evaluate(double const* const* parameters, double* residuals,
                               double** jacobians) const {
  residuals[0] = inv_sigma_ * (parameters[0][0] - mean_);
  if (jacobians != nullptr && jacobians[0] != nullptr) jacobians[0][0] = inv_sigma_;
  return true;
}

}  // namespace rio
}  // namespace coral_introspection
