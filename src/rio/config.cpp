#include "coral_introspection/rio/config.hpp"

#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace rio {

using coral::Problems;

std::string UncertaintyConfig::validate() const {
  return Problems()
      .nested("noise", noise.validate())
      .require(covariance_scale > 0.0, "covariance_scale", "> 0", covariance_scale)
      .require(isotropic_sigma > 0.0, "isotropic_sigma", "> 0 m", isotropic_sigma)
      .require(ablation_shrink > 0.0 && ablation_shrink <= 1.0, "ablation_shrink", "in (0, 1]",
               ablation_shrink)
      .require(sigma_doppler > 0.0, "sigma_doppler", "> 0 m/s", sigma_doppler)
      .require(doppler_sigma_isotropic > 0.0, "doppler_sigma_isotropic", "> 0 m/s",
               doppler_sigma_isotropic)
      .require(min_variance > 0.0, "min_variance", "> 0 m^2", min_variance)
      .str();
}

std::string FrontEndConfig::validate() const {
  return Problems()
      .require(min_range >= 0.0 && min_range < max_range, "min_range", "in [0, max_range) m",
               min_range)
      .require(max_azimuth > 0.0, "max_azimuth", "> 0 rad", max_azimuth)
      .require(max_elevation > 0.0, "max_elevation", "> 0 rad", max_elevation)
      .nested("doppler", doppler.validate())
      .require(static_threshold > 0.0, "static_threshold", "> 0 m/s", static_threshold)
      .require(zero_velocity_speed >= 0.0, "zero_velocity_speed", ">= 0 m/s", zero_velocity_speed)
      .require(zero_velocity_min_points >= 3, "zero_velocity_min_points", ">= 3",
               zero_velocity_min_points)
      .str();
}

std::string AssociationConfig::validate() const {
  return Problems()
      .require(gate_sigma > 0.0, "gate_sigma", "> 0", gate_sigma)
      .require(max_search_radius > 0.0, "max_search_radius", "> 0 m", max_search_radius)
      .require(min_observations >= 2, "min_observations", ">= 2", min_observations)
      .require(max_map_landmarks >= 0, "max_map_landmarks", ">= 0", max_map_landmarks)
      .require(outlier_chi2 > 0.0, "outlier_chi2", "> 0", outlier_chi2)
      .str();
}

std::string SolverConfig::validate() const {
  return Problems()
      .require(window_size >= 2 && window_size <= 50, "window_size", "in [2, 50]", window_size)
      .require(max_iterations >= 1, "max_iterations", ">= 1", max_iterations)
      .require(max_solver_time > 0.0, "max_solver_time", "> 0 s", max_solver_time)
      .require(loss == "none" || loss == "huber" || loss == "cauchy", "loss",
               "one of none, huber, cauchy", loss)
      .require(loss_scale > 0.0, "loss_scale", "> 0", loss_scale)
      .str();
}

std::string InitConfig::validate() const {
  return Problems()
      .require(static_duration > 0.0, "static_duration", "> 0 s", static_duration)
      .require(max_gyro_std > 0.0, "max_gyro_std", "> 0 rad/s", max_gyro_std)
      .require(max_acc_std > 0.0, "max_acc_std", "> 0 m/s^2", max_acc_std)
      .require(timeout >= static_duration, "timeout", ">= static_duration s", timeout)
      .require(sigma_roll_pitch > 0.0 && sigma_yaw > 0.0 && sigma_position > 0.0 &&
                   sigma_velocity > 0.0 && sigma_acc_bias > 0.0 && sigma_gyro_bias > 0.0,
               "init sigmas must all be > 0")
      .str();
}

std::string ZeroVelocityConfig::validate() const {
  return Problems()
      .require(sigma_velocity > 0.0, "sigma_velocity", "> 0 m/s", sigma_velocity)
      .require(max_gyro_std > 0.0, "max_gyro_std", "> 0 rad/s", max_gyro_std)
      .require(max_gyro_rate > 0.0, "max_gyro_rate", "> 0 rad/s", max_gyro_rate)
      .require(min_gyro_samples >= 2, "min_gyro_samples", ">= 2", min_gyro_samples)
      .str();
}

std::string HealthConfig::validate() const {
  return Problems()
      .require(max_speed > 0.0, "max_speed", "> 0 m/s", max_speed)
      .require(max_acc_bias > 0.0, "max_acc_bias", "> 0 m/s^2", max_acc_bias)
      .require(max_gyro_bias > 0.0, "max_gyro_bias", "> 0 rad/s", max_gyro_bias)
      .require(max_correction > 0.0, "max_correction", "> 0 m", max_correction)
      .require(max_imu_gap > 0.0, "max_imu_gap", "> 0 s", max_imu_gap)
      .str();
}

std::string RioConfig::validate() const {
  const double det = extrinsics.R.determinant();
  return Problems()
      .nested("imu", imu.validate())
      .require(extrinsics.R.allFinite() && std::abs(det - 1.0) < 1e-6 &&
                   (extrinsics.R * extrinsics.R.transpose() - Mat3::Identity()).norm() < 1e-6,
               "extrinsics rotation must be a rotation matrix")
      .require(extrinsics.t.allFinite(), "extrinsics translation must be finite")
      .require(std::abs(radar_time_offset) < 1.0, "radar_time_offset", "in (-1, 1) s",
               radar_time_offset)
      .nested("time_offset", time_offset.validate())
      // The prior inside the bound (Ceres needs the start value there; at the bound it would
      // count towards a refusal from the first frame).
      .require(!time_offset.estimate || std::abs(radar_time_offset) < time_offset.max_abs,
               "radar_time_offset", "inside time_offset/max_abs when estimated", radar_time_offset)
      .nested("uncertainty", uncertainty.validate())
      .nested("front_end", front_end.validate())
      .nested("association", association.validate())
      .nested("solver", solver.validate())
      .nested("init", init.validate())
      .nested("zero_velocity", zero_velocity.validate())
      .nested("health", health.validate())
      .nested("barometer", barometer.validate())
      .str();
}

}  // namespace rio
}  // namespace coral_introspection
