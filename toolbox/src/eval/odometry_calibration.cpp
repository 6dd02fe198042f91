#include "coral_introspection/eval/odometry_calibration.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace eval {

namespace {

double wrapped(double a) { return std::atan2(std::sin(a), std::cos(a)); }

// The step k -> k+1 of a chain of poses (pose k+1 in pose k's frame).
Eigen::Isometry3d step(const coral::Isometries& T, std::size_t k) {
  return T[k].inverse() * T[k + 1];
}

}  // namespace

bool fitOdometryYaw(const coral::Isometries& T_world_odom,
                    const std::vector<std::optional<Eigen::Isometry3d>>& measured, int min_steps,
                    OdometryYawModel* model, std::string* error) {
  *model = OdometryYawModel();
  if (T_world_odom.size() < 2 || measured.size() != T_world_odom.size() - 1)
    return coral::fail(error, "odometry calibration: one measured step slot per odometry step");
  if (min_steps < 2) return coral::fail(error, "odometry calibration: min_steps must be >= 2");
  // Normal equations of err = gain * yaw + bias_per_m * length.
  Eigen::Matrix2d AtA = Eigen::Matrix2d::Zero();
  Eigen::Vector2d Atb = Eigen::Vector2d::Zero();
  std::vector<Eigen::Vector3d> rows;  // (yaw, length, err) per measured step
  for (std::size_t k = 0; k < measured.size(); ++k) {
    if (!measured[k]) continue;
    const Eigen::Isometry3d s = step(T_world_odom, k);
    const double yaw = coral::yawOf(s.linear());
    const double err = wrapped(yaw - coral::yawOf(measured[k]->linear()));
    const Eigen::Vector2d a(yaw, s.translation().head<2>().norm());
    AtA += a * a.transpose();
    Atb += a * err;
    rows.emplace_back(a.x(), a.y(), err);
  }
  model->steps = static_cast<int>(rows.size());
  if (model->steps < min_steps)
    return coral::fail(error, "odometry calibration: " + std::to_string(model->steps) +
                                  " measured steps, fewer than " + std::to_string(min_steps));
  // Conditioned: the smallest eigenvalue of the normalised normal matrix well above 0.
  const Eigen::Vector2d scale = AtA.diagonal().cwiseSqrt();
  if (!(scale.minCoeff() > 0.0))
    return coral::fail(error, "odometry calibration: the measured steps never turn or never move");
  const Eigen::Matrix2d N = scale.asDiagonal().inverse() * AtA * scale.asDiagonal().inverse();
  if (Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(N).eigenvalues().minCoeff() < 1e-3)
    return coral::fail(error,
                       "odometry calibration: the measured steps turn in proportion to their "
                       "length; the turn and the distance terms cannot be told apart");
  const Eigen::Vector2d x = AtA.ldlt().solve(Atb);
  model->gain = x.x();
  model->bias_per_m = x.y();
  double before = 0.0, after = 0.0;
  for (const Eigen::Vector3d& r : rows) {
    before += r.z() * r.z();
    const double e = r.z() - model->gain * r.x() - model->bias_per_m * r.y();
    after += e * e;
  }
  model->rms_before = std::sqrt(before / model->steps);
  model->rms_after = std::sqrt(after / model->steps);
  return true;
}

coral::Isometries correctOdometryYaw(const coral::Isometries& T_world_odom,
                                     const OdometryYawModel& model) {
  if (T_world_odom.empty()) return {};
  coral::Isometries out = {T_world_odom[0]};
  for (std::size_t k = 0; k + 1 < T_world_odom.size(); ++k) {
    Eigen::Isometry3d s = step(T_world_odom, k);
    const double yaw = coral::yawOf(s.linear());
    const double err = model.gain * yaw + model.bias_per_m * s.translation().head<2>().norm();
    // Rz(-err) applied after the step's rotation: the step turns by yaw - err, its roll and
    // pitch (zero on a planar log) kept.
    s.linear() = Eigen::AngleAxisd(-err, Eigen::Vector3d::UnitZ()).toRotationMatrix() * s.linear();
    out.push_back(out.back() * s);
  }
  return out;
}

}  // namespace eval
}  // namespace coral_introspection
