// Doppler introspection for radars that measure radial velocity (paper:
// radar_point_uncertainty_slam, Sec. III-C, Eq. 9-12). A static point k seen along the unit
// bearing d_k = p_k / |p_k| has radial velocity v_r,k = -d_k^T v_s when the sensor moves with
// v_s (sensor frame) and v_r is positive away from the sensor (Eq. 9 without IMU lever arm).
// From one scan this gives a robust ego-velocity estimate and a consistency check of the
// odometry's sensor velocity that needs no second scan.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace radar {

struct DopplerConfig {
  double sigma_doppler = 0.05;     // [m/s] Doppler noise added to every residual variance
  double ransac_threshold = 0.15;  // [m/s] |residual| of an inlier (static point)
  int ransac_iterations = 100;
  double min_inlier_ratio = 0.5;  // below: no valid estimate (scene dominated by movers)
  int min_points = 8;             // fewer finite points with a bearing: no estimate
  double confidence = 0.99;       // chi-square quantile of the consistency threshold
  bool radial_velocity_positive_away = true;  // sign convention of the sensor's v_r
  unsigned seed = 42;                         // RANSAC sampling (deterministic)
  // [m/s] standard deviation (per axis) of the velocity under test, added to the Doppler
  // estimate's covariance in the consistency test. 0 = treat it as exact.
  double sigma_reference_velocity = 0.0;
  std::string validate() const;  // empty when valid
};

struct EgoVelocityResult {
  bool valid = false;
  coral::Vec3 velocity = coral::Vec3::Zero();        // sensor velocity in the sensor frame [m/s]
  coral::Mat3 covariance = coral::Mat3::Identity();  // of velocity [m^2/s^2]; planar: (2,2) = +inf
  std::size_t num_points = 0, num_inliers = 0;
  double inlier_ratio = 0, median_residual = 0;  // median |residual| of the inliers [m/s]
  bool planar = false;  // every point has z == 0: velocity.z() unobservable, reported as 0
  std::string error;
};

// RANSAC (minimal sets of 3 points, 2 when planar) then iterated weighted least squares on
// the inliers with weights 1 / (sigma_doppler^2 + J_k Sigma_k J_k^T) (Eq. 10-12), where
// Sigma_k = point_cov[k] (sensor frame, e.g. from attachCovariances) if given. Never throws.
EgoVelocityResult estimateEgoVelocity(const coral::Points& points,
                                      const std::vector<double>& radial_velocity,
                                      const DopplerConfig& cfg,
                                      const coral::Covariances* point_cov = nullptr);

struct ConsistencyResult {
  bool valid = false;
  bool consistent = false;
  double chi2 = 0, threshold = 0;  // chi2 <= threshold: consistent
  int dof = 0;                     // 3, or 2 for planar scans
  std::size_t num_inliers = 0;
  coral::Vec3 velocity_doppler = coral::Vec3::Zero();
  std::string error;
};

// Tests the odometry's sensor velocity (sensor frame of the scan) against the Doppler
// measurements of the static points (inliers of estimateEgoVelocity). The statistic is
// the part of sum_k e_k(v)^2 / s_k^2 that depends on v (e_k: Eq. 9 residual, s_k^2: Eq. 12
// variance + sigma_doppler^2): chi2 = (v - v_D)^T Cov(v_D)^-1 (v - v_D), chi-square with
// dof = number of observable velocity components. Cov(v_D) is inflated by the reduced
// chi-square of the fit when that exceeds 1 (real Doppler noise larger than configured).
// sensor_velocity_cov (optional, sensor frame, e.g. the odometry's twist covariance) is
// added to Cov(v_D), as is sigma_reference_velocity^2 I.
ConsistencyResult checkVelocityConsistency(const coral::Points& points,
                                           const std::vector<double>& radial_velocity,
                                           const coral::Vec3& sensor_velocity,
                                           const DopplerConfig& cfg,
                                           const coral::Covariances* point_cov = nullptr,
                                           const coral::Mat3* sensor_velocity_cov = nullptr);

// Variance of the Eq. 9 residual of a static point p (sensor frame) for the sensor
// velocity v: sigma_doppler^2 + J Sigma_k J^T with J = v^T (I - d d^T) / |p|, d = p / |p|
// (Eq. 10-12): only the bearing part of Sigma_k moves the predicted Doppler.
double dopplerResidualVariance(const coral::Vec3& p, const coral::Vec3& v,
                               const coral::Mat3& point_cov, double sigma_doppler);

// Quantile of the chi-square distribution with dof degrees of freedom (1 <= dof <= 100):
// P(X <= x) = p. Used for the consistency threshold.
double chiSquareQuantile(double p, int dof);

}  // namespace radar
}  // namespace coral_introspection
