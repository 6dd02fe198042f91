#include "coral_introspection/eval/doppler_simulation.hpp"

#include <cmath>

namespace coral_introspection {
namespace eval {

namespace {
coral::Vec3 fromPolar(double r, double az, double el) {
  return r * coral::Vec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
}
}  // namespace

DopplerSimScan simulateDopplerScan(const coral::Vec3& v_sensor, const DopplerSimConfig& cfg,
                                   std::mt19937& rng) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> g;
  const bool planar = cfg.elevation_half_fov <= 0.0;
  const double sign = cfg.radial_velocity_positive_away ? -1.0 : 1.0;
  const radar::RadarNoiseConfig& pn = cfg.position_noise;
  DopplerSimScan s;
  for (int i = 0; i < cfg.num_points; ++i) {
    const double r = cfg.min_range + (cfg.max_range - cfg.min_range) * u01(rng);
    const double az = cfg.azimuth_half_fov * (2.0 * u01(rng) - 1.0);
    const double el = planar ? 0.0 : cfg.elevation_half_fov * (2.0 * u01(rng) - 1.0);
    const coral::Vec3 d = fromPolar(1.0, az, el);
    // Eq. 9 for a static point, plus Gaussian Doppler noise.
    double vr = sign * d.dot(v_sensor) + cfg.sigma_doppler * g(rng);
    const bool moving = u01(rng) < cfg.outlier_fraction;
    if (moving) {
      const double speed =
          cfg.mover_min_speed + (cfg.mover_max_speed - cfg.mover_min_speed) * u01(rng);
      vr += u01(rng) < 0.5 ? speed : -speed;
    }
    const double el_meas = planar ? 0.0 : el + pn.sigma_elevation * g(rng);
    s.points.push_back(
        fromPolar(r + pn.sigma_range * g(rng), az + pn.sigma_azimuth * g(rng), el_meas));
    s.radial_velocity.push_back(vr);
    s.is_static.push_back(!moving);
  }
  return s;
}

}  // namespace eval
}  // namespace coral_introspection
