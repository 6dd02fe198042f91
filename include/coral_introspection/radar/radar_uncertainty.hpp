// Polar measurement model of radar points (paper: radar_point_uncertainty_slam, Sec. III-B,
// Eq. 3-8): a point measured as range r, azimuth theta and elevation phi has the Cartesian
// covariance Sigma_k = A_k diag(sigma_r^2, Sigma_Omega) A_k^T, small along the beam and
// growing with r across it.
#pragma once

#include <string>

#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace radar {

// Standard deviations of the polar measurement noise (Eq. 3-4). Units: m, rad.
struct RadarNoiseConfig {
  double sigma_range = 0.0144;     // [m] sigma_r
  double sigma_azimuth = 0.00524;  // [rad] sigma_theta
  double sigma_elevation = 0.0;    // [rad] sigma_phi (0 for a spinning 2D radar)

  // Presets. The largest detection error e is taken as one resolution cell of the
  // datasheet and read as the 3-sigma bound (the paper's choice, Sec. IV-A): sigma = e / 3.
  // Navtech CTS350-X (Oxford Radar RobotCar): range bin 0.0432 m, azimuth step 0.9 deg;
  // 3-sigma = one range bin and one azimuth step. 2D: no elevation.
  static RadarNoiseConfig oxfordCts350x();
  // TI AWR1843 (BOOST antenna): range resolution about 0.044 m (4 GHz sweep), angular
  // resolution about 15 deg azimuth and 58 deg elevation (one elevated TX antenna).
  static RadarNoiseConfig tiAwr1843();
  // ZF FRGen21 (View-of-Delft): range resolution 0.2 m, azimuth and elevation resolution
  // 1.5 deg (View-of-Delft paper, sensor table).
  static RadarNoiseConfig vodZfFrgen21();

  std::string validate() const;  // empty when valid
};

// Jacobian A_k of Eq. 7 for the point p (sensor frame, sensor at 0): the columns are
// dp/dr, dp/dtheta, dp/dphi of p = r (cos phi cos theta, cos phi sin theta, sin phi).
// This equals [Omega, -r Omega^ N(Omega)] with the tangent basis N chosen so that
// delta_Omega = (delta_theta, delta_phi). Note dz/dphi = +r cos(phi).
coral::Mat3 polarJacobian(const coral::Vec3& p);

// Sigma_k = A_k diag(sigma_r^2, sigma_theta^2, sigma_phi^2) A_k^T (Eq. 8) in the sensor
// frame. dim == 2: the point is taken in the xy plane (range and azimuth only); the
// result has zero z row and column. A point at the sensor origin gets
// sigma_range^2 * I (direction undefined).
coral::Mat3 pointCovariance(const coral::Vec3& p, const RadarNoiseConfig& cfg, int dim);

// Fills scan.covariances (one per point) from the polar model. Points must be in the
// sensor frame of the scan, i.e. call this before transformScan (which then rotates the
// covariances). Non-finite points get a NaN covariance. Returns false with *error set on
// an invalid config or dim; never throws.
bool attachCovariances(coral::Scan& scan, const RadarNoiseConfig& cfg, int dim, std::string* error);

}  // namespace radar
}  // namespace coral_introspection
