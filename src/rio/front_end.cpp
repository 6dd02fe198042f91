#include "coral_introspection/rio/front_end.hpp"

#include <algorithm>
#include <cmath>

#include "coral_introspection/radar/doppler_fit.hpp"
#include "coral_introspection/rio/point_uncertainty.hpp"

namespace coral_introspection {
namespace rio {

FrontEndResult processRadarFrame(const RadarFrame& frame, const RioConfig& cfg,
                                 const Vec3* v_radar_predicted) {
  const FrontEndConfig& fe = cfg.front_end;
  FrontEndResult out;
  out.has_doppler =
      !frame.radial_velocity.empty() && frame.radial_velocity.size() == frame.points.size();
  const bool has_intensity = frame.intensity.size() == frame.points.size();
  const double sign = fe.radial_velocity_positive_away ? -1.0 : 1.0;
  coral::Points pts;
  coral::Covariances covs;
  std::vector<double> m;
  for (std::size_t i = 0; i < frame.points.size(); ++i) {
    const Vec3& p = frame.points[i];
    const double r = p.norm();
    const double vr = out.has_doppler ? frame.radial_velocity[i] : 0.0;
    const bool keep = p.allFinite() && std::isfinite(vr) && r >= fe.min_range &&
                      r <= fe.max_range && std::abs(std::atan2(p.y(), p.x())) <= fe.max_azimuth &&
                      std::abs(std::asin(std::clamp(p.z() / r, -1.0, 1.0))) <= fe.max_elevation &&
                      (!has_intensity || frame.intensity[i] >= fe.min_intensity);
    if (!keep) {
      ++out.dropped;
      continue;
    }
    RadarPoint rp{p, sign * vr, pointCovariance(p, cfg.uncertainty)};
    out.points.push_back(rp);
    pts.push_back(p);
    covs.push_back(rp.cov);
    m.push_back(vr);
  }
  if (!out.has_doppler || out.points.empty()) return out;

  // Static points = consensus of Eq. 9 over the scan (robust to moving objects).
  radar::DopplerConfig dc = fe.doppler;
  dc.radial_velocity_positive_away = fe.radial_velocity_positive_away;
  dc.sigma_doppler = cfg.uncertainty.sigma_doppler;
  const radar::DopplerFit fit = radar::fitDoppler(pts, m, dc, &covs);
  if (fit.valid) {
    out.doppler_fit = true;
    out.v_radar = fit.velocity;
    for (std::size_t k : fit.inliers) out.static_points.push_back(static_cast<int>(k));
    std::sort(out.static_points.begin(), out.static_points.end());
    // Standing: zero velocity passes the Doppler consistency test of the fit (chi-square
    // at DopplerConfig::confidence), and the fitted speed is small.
    out.standing = static_cast<int>(fit.inliers.size()) >= fe.zero_velocity_min_points &&
                   fit.velocity.norm() < fe.zero_velocity_speed &&
                   radar::testVelocity(fit, Vec3::Zero(), dc).consistent;
    return out;
  }
  // No consensus: points consistent with the predicted velocity, if there is one; a scan
  // whose Doppler is (almost) all zero is a standing radar.
  int zero = 0;
  for (std::size_t k = 0; k < out.points.size(); ++k) {
    const RadarPoint& rp = out.points[k];
    zero += std::abs(rp.m) < fe.zero_velocity_speed;
    if (v_radar_predicted &&
        std::abs(rp.m - rp.p.normalized().dot(*v_radar_predicted)) < fe.static_threshold)
      out.static_points.push_back(static_cast<int>(k));
  }
  out.standing =
      zero >= fe.zero_velocity_min_points && 2 * zero > static_cast<int>(out.points.size());
  return out;
}

}  // namespace rio
}  // namespace coral_introspection
