#include "coral_introspection/rio/point_uncertainty.hpp"

#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace rio {

Mat3 pointCovariance(const Vec3& p, const UncertaintyConfig& cfg) {
  const double iso2 = cfg.isotropic_sigma * cfg.isotropic_sigma;
  const double r = p.norm();
  if (cfg.mode == UncertaintyMode::kNone || !(r > 1e-9))
    return cfg.covariance_scale * iso2 * Mat3::Identity();
  const Vec3 d = p / r;
  const Mat3 along = d * d.transpose();
  Mat3 S;
  if (!cfg.ablation_replace && cfg.mode != UncertaintyMode::kFull) {
    radar::RadarNoiseConfig shrunk = cfg.noise;  // Sec. IV-B: the removed sigma "very small"
    if (cfg.mode == UncertaintyMode::kNoRange) {
      shrunk.sigma_range *= cfg.ablation_shrink;
    } else {
      shrunk.sigma_azimuth *= cfg.ablation_shrink;
      shrunk.sigma_elevation *= cfg.ablation_shrink;
    }
    return cfg.covariance_scale * radar::pointCovariance(p, shrunk, 3);
  }
  switch (cfg.mode) {
    case UncertaintyMode::kFull:
      S = radar::pointCovariance(p, cfg.noise, 3);
      break;
    case UncertaintyMode::kNoRange: {
      radar::RadarNoiseConfig bearing_only = cfg.noise;
      bearing_only.sigma_range = 0.0;  // Eq. 8 without its range term
      S = radar::pointCovariance(p, bearing_only, 3) + iso2 * along;
      break;
    }
    case UncertaintyMode::kNoBearing:
    default:
      S = cfg.noise.sigma_range * cfg.noise.sigma_range * along + iso2 * (Mat3::Identity() - along);
      break;
  }
  return cfg.covariance_scale * S;
}

double dopplerVariance(const Vec3& p, const Vec3& v_radar, const UncertaintyConfig& cfg) {
  if (cfg.mode == UncertaintyMode::kNone)
    return cfg.doppler_sigma_isotropic * cfg.doppler_sigma_isotropic;
  return radar::dopplerResidualVariance(p, v_radar, pointCovariance(p, cfg), cfg.sigma_doppler);
}

}  // namespace rio
}  // namespace coral_introspection
