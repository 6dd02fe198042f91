#include "coral_introspection/radar/doppler_fit.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>

#include "coral_introspection/coral/statistics.hpp"

namespace coral_introspection {
namespace radar {

namespace {

struct Obs {
  std::size_t index;  // into the input points
  coral::Vec3 d;      // unit bearing d_k
  double range;       // |p_k|
  double m;           // d_k^T v_s expected for a static point (sign-normalised v_r)
  coral::Mat3 cov;    // point covariance (zero if unknown)
};

double residualVariance(const Obs& o, const coral::Vec3& v, double sigma_doppler) {
  return dopplerResidualVariance(o.d * o.range, v, o.cov, sigma_doppler);
}

double absResidual(const Obs& o, const coral::Vec3& v) { return std::abs(o.d.dot(v) - o.m); }

}  // namespace

double dopplerResidualVariance(const coral::Vec3& p, const coral::Vec3& v,
                               const coral::Mat3& point_cov, double sigma_doppler) {
  const double r = p.norm();
  const coral::Vec3 d = p / r;
  // J = d(d^T v)/dp = v^T (I - d d^T) / |p|  (Eq. 11-12).
  const coral::Vec3 J = (v - d * d.dot(v)) / r;
  return sigma_doppler * sigma_doppler + J.dot(point_cov * J);
}

DopplerFit fitDoppler(const coral::Points& points, const std::vector<double>& radial_velocity,
                      const DopplerConfig& cfg, const coral::Covariances* point_cov) {
  DopplerFit f;
  auto fail = [&f](const std::string& why) {
    f.valid = false;
    f.error = why;
    return f;
  };
  if (std::string e = cfg.validate(); !e.empty()) return fail(e);
  if (radial_velocity.size() != points.size())
    return fail("radial_velocity size differs from points size");
  const bool with_cov = point_cov != nullptr && point_cov->size() == points.size();
  if (point_cov != nullptr && !with_cov) return fail("point_cov size differs from points");

  // Eq. 9: v_r = -d^T v_s for a static point when v_r is positive away from the sensor.
  const double sign = cfg.radial_velocity_positive_away ? -1.0 : 1.0;
  std::vector<Obs> obs;
  bool planar = true;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const coral::Vec3& p = points[i];
    const double r = p.norm();
    if (!p.allFinite() || !(r > 1e-6) || !std::isfinite(radial_velocity[i])) continue;
    coral::Mat3 cov = with_cov ? (*point_cov)[i] : coral::Mat3::Zero();
    if (!cov.allFinite()) cov.setZero();
    obs.push_back({i, p / r, r, sign * radial_velocity[i], cov});
    if (std::abs(p.z()) > 1e-9 * r) planar = false;
  }
  f.num_points = obs.size();
  f.dim = planar ? 2 : 3;
  const int n = f.dim;
  if (obs.size() < static_cast<std::size_t>(std::max(cfg.min_points, n + 1)))
    return fail("too few usable points (" + std::to_string(obs.size()) + ")");

  // RANSAC: a minimal set of n bearings fixes v exactly; keep the largest consensus.
  std::mt19937 rng(cfg.seed);
  std::uniform_int_distribution<std::size_t> pick(0, obs.size() - 1);
  coral::Vec3 best_v = coral::Vec3::Zero();
  std::size_t best_count = 0;
  for (int it = 0; it < cfg.ransac_iterations; ++it) {
    Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
    coral::Vec3 b = coral::Vec3::Zero();
    std::size_t idx[3] = {pick(rng), pick(rng), pick(rng)};
    for (int k = 0; k < n; ++k) {
      A.row(k).head(n) = obs[idx[k]].d.head(n).transpose();
      b(k) = obs[idx[k]].m;
    }
    if (std::abs(A.topLeftCorner(n, n).determinant()) < 1e-3) continue;  // near-collinear
    coral::Vec3 v = coral::Vec3::Zero();
    v.head(n) = A.topLeftCorner(n, n).partialPivLu().solve(b.head(n));
    std::size_t count = 0;
    for (const Obs& o : obs) count += absResidual(o, v) < cfg.ransac_threshold;
    if (count > best_count) best_count = count, best_v = v;
  }
  if (best_count < static_cast<std::size_t>(n + 1)) return fail("RANSAC found no consensus");

  // Iterated WLS on the inliers, weights from the propagated covariance (Eq. 10-12)
  // evaluated at the current estimate; inliers re-selected with the refined velocity.
  coral::Vec3 v = best_v;
  Eigen::MatrixXd info(n, n);
  std::vector<const Obs*> in;
  for (int iter = 0; iter < 4; ++iter) {
    in.clear();
    for (const Obs& o : obs)
      if (absResidual(o, v) < cfg.ransac_threshold) in.push_back(&o);
    if (in.size() < static_cast<std::size_t>(n + 1)) return fail("too few inliers");
    info.setZero();
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
    for (const Obs* o : in) {
      const double w = 1.0 / residualVariance(*o, v, cfg.sigma_doppler);
      info.noalias() += w * o->d.head(n) * o->d.head(n).transpose();
      rhs += w * o->m * o->d.head(n);
    }
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(info);
    if (ldlt.info() != Eigen::Success || ldlt.rcond() < 1e-9)
      return fail("bearings of the inliers do not constrain the velocity");
    v.head(n) = ldlt.solve(rhs);
  }

  std::vector<double> abs_res;
  double chi2 = 0.0;
  for (const Obs* o : in) {
    const double e = absResidual(*o, v);
    abs_res.push_back(e);
    chi2 += e * e / residualVariance(*o, v, cfg.sigma_doppler);
    f.inliers.push_back(o->index);
  }
  f.median_residual =
      coral::quantile(std::move(abs_res), 0.5);  // a measured residual (upper middle)
  f.reduced_chi2 = chi2 / static_cast<double>(in.size() - n);
  f.velocity = v;
  f.covariance = info.inverse();
  f.inlier_ratio = static_cast<double>(in.size()) / static_cast<double>(obs.size());
  if (f.inlier_ratio < cfg.min_inlier_ratio) return fail("inlier ratio below min_inlier_ratio");
  f.valid = true;
  return f;
}

}  // namespace radar
}  // namespace coral_introspection
