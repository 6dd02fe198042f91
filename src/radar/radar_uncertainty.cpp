#include "coral_introspection/radar/radar_uncertainty.hpp"

#include "coral_introspection/coral/validation.hpp"

#include <cmath>
#include <limits>

namespace coral_introspection {
namespace radar {

namespace {
constexpr double kDeg = M_PI / 180.0;

RadarNoiseConfig fromLargestErrors(double range_m, double azimuth_deg, double elevation_deg) {
  // The largest detection error is read as the 3-sigma bound (paper Sec. IV-A).
  RadarNoiseConfig c;
  c.sigma_range = range_m / 3.0;
  c.sigma_azimuth = azimuth_deg * kDeg / 3.0;
  c.sigma_elevation = elevation_deg * kDeg / 3.0;
  return c;
}
}  // namespace

RadarNoiseConfig RadarNoiseConfig::oxfordCts350x() { return fromLargestErrors(0.0432, 0.9, 0.0); }
RadarNoiseConfig RadarNoiseConfig::tiAwr1843() { return fromLargestErrors(0.044, 15.0, 58.0); }
RadarNoiseConfig RadarNoiseConfig::vodZfFrgen21() { return fromLargestErrors(0.2, 1.5, 1.5); }

std::string RadarNoiseConfig::validate() const {
  return coral::Problems()
      .require(sigma_range > 0.0 && sigma_range < 10.0, "sigma_range", "in (0, 10) m", sigma_range)
      .require(sigma_azimuth > 0.0 && sigma_azimuth < M_PI / 2, "sigma_azimuth", "in (0, pi/2) rad",
               sigma_azimuth)
      .require(sigma_elevation >= 0.0 && sigma_elevation < M_PI / 2, "sigma_elevation",
               "in [0, pi/2) rad", sigma_elevation)
      .str();
}

coral::Mat3 polarJacobian(const coral::Vec3& p) {
  const double rho = p.head<2>().norm();  // r cos(phi)
  const double r = p.norm();
  const double theta = std::atan2(p.y(), p.x());
  const double phi = std::atan2(p.z(), rho);
  const double ct = std::cos(theta), st = std::sin(theta);
  const double cp = std::cos(phi), sp = std::sin(phi);
  coral::Mat3 A;
  // Column 0: Omega = dp/dr (Eq. 7, first block).
  // Column 1: dp/dtheta = r cos(phi) (-sin theta, cos theta, 0).
  // Column 2: dp/dphi = r (-sin phi cos theta, -sin phi sin theta, +cos phi); the sign of
  //           dz/dphi is the one the authors' code gets wrong.
  A << cp * ct, -r * cp * st, -r * sp * ct,  //
      cp * st, r * cp * ct, -r * sp * st,    //
      sp, 0.0, r * cp;
  return A;
}

coral::Mat3 pointCovariance(const coral::Vec3& p, const RadarNoiseConfig& cfg, int dim) {
  const double sr2 = cfg.sigma_range * cfg.sigma_range;
  coral::Vec3 q = p;
  if (dim == 2) q.z() = 0.0;
  if (!(q.norm() > 0.0)) {
    coral::Mat3 S = sr2 * coral::Mat3::Identity();
    if (dim == 2) S(2, 2) = 0.0;
    return S;
  }
  const coral::Mat3 A = polarJacobian(q);
  // Eq. 8 with diag(sigma_r^2, Sigma_Omega) (Eq. 4); in 2D only range and azimuth.
  const coral::Vec3 var(sr2, cfg.sigma_azimuth * cfg.sigma_azimuth,
                        dim == 2 ? 0.0 : cfg.sigma_elevation * cfg.sigma_elevation);
  coral::Mat3 S = A * var.asDiagonal() * A.transpose();
  if (dim == 2) {
    S.row(2).setZero();
    S.col(2).setZero();
  }
  return 0.5 * (S + S.transpose());
}

bool attachCovariances(coral::Scan& scan, const RadarNoiseConfig& cfg, int dim,
                       std::string* error) {
  std::string msg = cfg.validate();
  if (msg.empty() && dim != 2 && dim != 3)
    msg = "dim must be 2 or 3 (got " + std::to_string(dim) + ")";
  if (!msg.empty()) {
    if (error) *error = msg;
    return false;
  }
  const coral::Mat3 nan_cov = coral::Mat3::Constant(std::numeric_limits<double>::quiet_NaN());
  scan.covariances.clear();
  scan.covariances.reserve(scan.points.size());
  for (const coral::Vec3& p : scan.points)
    scan.covariances.push_back(p.allFinite() ? pointCovariance(p - scan.origin, cfg, dim)
                                             : nan_cov);
  return true;
}

}  // namespace radar
}  // namespace coral_introspection
