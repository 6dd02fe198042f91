// Robust Doppler ego-velocity fit shared by estimateEgoVelocity and
// checkVelocityConsistency (doppler.hpp is the public API; this exposes the internals the
// consistency test needs: information matrix and fit quality).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "coral_introspection/radar/doppler.hpp"

namespace coral_introspection {
namespace radar {

struct DopplerFit {
  bool valid = false;
  int dim = 3;                                 // 2 when every point has z == 0 (vz unobservable)
  coral::Vec3 velocity = coral::Vec3::Zero();  // z = 0 when dim == 2
  Eigen::MatrixXd covariance;                  // dim x dim, (H^T W H)^-1 of the final WLS
  std::vector<std::size_t> inliers;            // indices into the input points
  std::size_t num_points = 0;                  // usable points (finite, nonzero range, finite v_r)
  double inlier_ratio = 0.0;
  double median_residual = 0.0;  // median |e_k| over inliers [m/s]
  double reduced_chi2 = 0.0;     // sum w_k e_k^2 / (n_inliers - dim)
  std::string error;
};

// RANSAC on minimal sets (dim points), then iterated WLS on the inliers (Eq. 9-12).
DopplerFit fitDoppler(const coral::Points& points, const std::vector<double>& radial_velocity,
                      const DopplerConfig& cfg, const coral::Covariances* point_cov);

// The chi-square test of checkVelocityConsistency on an existing fit: is the sensor
// velocity v (sensor frame) consistent with the Doppler of the fit's inliers?
ConsistencyResult testVelocity(const DopplerFit& fit, const coral::Vec3& v,
                               const DopplerConfig& cfg,
                               const coral::Mat3* sensor_velocity_cov = nullptr);

}  // namespace radar
}  // namespace coral_introspection
