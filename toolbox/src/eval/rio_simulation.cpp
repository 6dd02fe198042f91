#include "coral_introspection/eval/rio_simulation.hpp"

#include <algorithm>
#include <cmath>
#include <random>

namespace coral_introspection {
namespace eval {

using rio::Mat3;
using rio::Quat;
using rio::Vec3;

RioSimConfig RioSimConfig::handheld(unsigned seed) {
  RioSimConfig c;
  c.seed = seed;
  // The TI recording's mounting: boresight about 45 deg right, 9 deg down, upside down.
  c.extrinsics.R =
      Quat(0.033880048164, -0.918681231167, 0.386946837543, 0.071757109423).toRotationMatrix();
  c.extrinsics.t = coral::Vec3(0.03, 0.03, -0.06);
  // About as many points per frame as the TI radar gives (40-60).
  c.num_reflectors = 250;
  c.max_points = 60;
  return c;
}

RioSimConfig RioSimConfig::vehicle(unsigned seed) {
  RioSimConfig c;
  c.seed = seed;
  c.trajectory = SimTrajectory::kVehicle;
  c.duration = 60.0;
  c.static_start = c.static_end = 3.0;
  c.extrinsics.t = coral::Vec3(1.5, 0.0, 0.5);  // forward-looking radar at the front bumper
  c.point_noise = {0.05, 0.01, 0.01};           // automotive 4D radar
  c.sigma_doppler = 0.05;
  c.max_range = 40.0;
  c.half_fov_elevation = 0.26;
  c.max_points = 150;
  c.num_reflectors = 2500;
  c.imu_noise = {0.004, 0.0003, 0.001, 0.00003, 9.81};
  return c;
}

namespace {

// Quintic smoothstep of the motion phase: 0 before, 1 after, C2 at both ends.
double phase(const RioSimConfig& c, double t) {
  const double t0 = c.static_start, t1 = c.duration - c.static_end;
  const double u = std::clamp((t - t0) / (t1 - t0), 0.0, 1.0);
  return u * u * u * (10.0 + u * (-15.0 + 6.0 * u));
}

Quat rpy(double roll, double pitch, double yaw) {
  return Quat(Eigen::AngleAxisd(yaw, coral::Vec3::UnitZ()) *
              Eigen::AngleAxisd(pitch, coral::Vec3::UnitY()) *
              Eigen::AngleAxisd(roll, coral::Vec3::UnitX()));
}

}  // namespace

StampedPose simulatedPose(const RioSimConfig& c, double t) {
  const double u = phase(c, t), tau = 2.0 * M_PI;
  StampedPose p;
  p.t = t;
  if (c.trajectory == SimTrajectory::kHandheld) {
    // Loops in a 4 x 3 m area at hand height, one net left turn plus wiggles, +-15 deg
    // roll / pitch; env vanishes (with its derivatives) at rest.
    const double env = std::pow(std::sin(M_PI * u), 2);
    p.p = coral::Vec3(0, 0, 1.2) + env * coral::Vec3(2.0 * std::sin(tau * 3 * u),
                                                     1.5 * std::sin(tau * 2 * u),
                                                     0.2 * std::sin(tau * 5 * u));
    p.q = rpy(env * 0.25 * std::sin(tau * 3 * u + 1.0), env * 0.2 * std::sin(tau * 5 * u + 2.0),
              tau * u + env * 0.8 * std::sin(tau * 6 * u));
  } else {
    // A figure eight (50 x 24 m) driven once, heading along the path tangent.
    const double th = tau * u;
    p.p = coral::Vec3(25.0 * std::sin(th), 12.0 * std::sin(2 * th), 0.5);
    const double yaw = std::atan2(24.0 * std::cos(2 * th), 25.0 * std::cos(th));
    const double env = std::pow(std::sin(M_PI * u), 2);
    p.q = rpy(env * 0.03 * std::sin(tau * 4 * u), env * 0.02 * std::sin(tau * 7 * u), yaw);
  }
  return p;
}

namespace {

struct Kinematics {
  StampedPose pose;
  coral::Vec3 v, a, omega;  // world velocity, world acceleration, body rate
};

// Derivatives by central differences of the smooth analytic pose (h = 1 ms: errors far
// below the simulated sensor noise).
Kinematics kinematics(const RioSimConfig& c, double t) {
  const double h = 1e-3;
  const StampedPose a = simulatedPose(c, t - h), b = simulatedPose(c, t),
                    d = simulatedPose(c, t + h);
  Kinematics k;
  k.pose = b;
  k.v = (d.p - a.p) / (2 * h);
  k.a = (d.p - 2 * b.p + a.p) / (h * h);
  k.omega = rio::logQ(a.q.conjugate() * d.q) / (2 * h);
  return k;
}

coral::Points reflectors(const RioSimConfig& c, std::mt19937& rng) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  coral::Points out;
  if (c.trajectory == SimTrajectory::kHandheld) {
    // Walls of a 10 x 8 m room (0-3 m high) and a few pieces of furniture.
    for (int i = 0; i < c.num_reflectors; ++i) {
      const double z = 3.0 * U(rng);
      const double s = U(rng);
      coral::Vec3 p;
      switch (i % 5) {
        case 0:
          p = coral::Vec3(-5 + 10 * s, -4, z);
          break;
        case 1:
          p = coral::Vec3(-5 + 10 * s, 4, z);
          break;
        case 2:
          p = coral::Vec3(-5, -4 + 8 * s, z);
          break;
        case 3:
          p = coral::Vec3(5, -4 + 8 * s, z);
          break;
        default:
          p = coral::Vec3(-4.5 + 9 * U(rng), -3.5 + 7 * U(rng), 1.5 * U(rng));
          break;
      }
      // Keep the walking area (|x| < 2.6, |y| < 2.1) free of furniture.
      if (i % 5 == 4 && std::abs(p.x()) < 2.6 && std::abs(p.y()) < 2.1) continue;
      out.push_back(p);
    }
  } else {
    // Objects scattered over 80 x 50 m, none within 3 m of the road.
    while (static_cast<int>(out.size()) < c.num_reflectors) {
      const coral::Vec3 p(-40 + 80 * U(rng), -25 + 50 * U(rng), 4.0 * U(rng));
      double dmin = 1e9;
      for (int k = 0; k < 200; ++k) {
        const coral::Vec3 q =
            simulatedPose(c,
                          c.static_start + (c.duration - c.static_start - c.static_end) * k / 199.0)
                .p;
        dmin = std::min(dmin, (p - q).head<2>().norm());
      }
      if (dmin > 3.0) out.push_back(p);
    }
  }
  return out;
}

// Barometer samples with their own generator (seeded from the sequence's seed), drawn after
// everything else so that a sequence with a barometer has the same IMU and radar data.
void simulateBarometer(const RioSimConfig& c, RioSequence* seq) {
  std::mt19937 rng(c.seed + 7919u);
  std::normal_distribution<double> N(0.0, 1.0);
  const double dt = 1.0 / c.baro_rate;
  double bias = c.baro_bias;
  for (int k = 0; k * dt <= c.duration + 1e-9; ++k) {
    const double h =
        c.site_altitude + simulatedPose(c, k * dt).p.z() + bias + c.baro_sigma * N(rng);
    seq->baro.push_back({k * dt, rio::altitudeToPressure(h)});
    bias += c.baro_bias_walk * std::sqrt(dt) * N(rng);
  }
}

}  // namespace

RioSequence simulateRio(const RioSimConfig& c) {
  std::mt19937 rng(c.seed);
  std::normal_distribution<double> N(0.0, 1.0);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  auto gauss = [&] { return coral::Vec3(N(rng), N(rng), N(rng)); };
  RioSequence seq;
  const coral::Points world = reflectors(c, rng);

  // IMU: specific force R^T (a + g e_z) and body rate, plus biases and white noise.
  const double dt = 1.0 / c.imu_rate;
  coral::Vec3 ba = c.acc_bias, bg = c.gyro_bias;
  const coral::Vec3 g(0, 0, c.imu_noise.gravity);
  for (int k = 0; k * dt <= c.duration + 1e-9; ++k) {
    const double t = k * dt;
    const Kinematics kin = kinematics(c, t);
    rio::ImuSample s;
    s.t = t;
    s.acc =
        kin.pose.q.conjugate() * (kin.a + g) + ba + c.imu_noise.acc_noise / std::sqrt(dt) * gauss();
    s.gyro = kin.omega + bg + c.imu_noise.gyro_noise / std::sqrt(dt) * gauss();
    seq.imu.push_back(s);
    ba += c.imu_noise.acc_bias_walk * std::sqrt(dt) * gauss();
    bg += c.imu_noise.gyro_bias_walk * std::sqrt(dt) * gauss();
  }

  // Radar frames: visible reflectors with polar noise; Doppler of a static point is
  // -d^T v_radar (positive away from the sensor), movers get an extra radial velocity.
  const radar::RadarNoiseConfig& pn = c.point_noise;
  for (int k = 1; k / c.radar_rate <= c.duration - 1e-9; ++k) {
    const double t = k / c.radar_rate;
    const Kinematics kin = kinematics(c, t);
    const coral::Mat3 R = kin.pose.q.toRotationMatrix();
    const coral::Mat3 R_wr = R * c.extrinsics.R;
    const coral::Vec3 p_wr = kin.pose.p + R * c.extrinsics.t;
    // Radar velocity in the radar frame (Eq. 9): R_E^T (R^T v + omega x t_E).
    const coral::Vec3 v_radar =
        c.extrinsics.R.transpose() * (R.transpose() * kin.v + kin.omega.cross(c.extrinsics.t));
    std::vector<std::pair<double, coral::Vec3>> visible;  // (range, point in the radar frame)
    for (const coral::Vec3& w : world) {
      const coral::Vec3 p = R_wr.transpose() * (w - p_wr);
      const double r = p.norm();
      if (r < 0.5 || r > c.max_range) continue;
      if (std::abs(std::atan2(p.y(), p.x())) > c.half_fov_azimuth) continue;
      if (std::abs(std::asin(p.z() / r)) > c.half_fov_elevation) continue;
      if (U(rng) > c.detection_probability) continue;
      visible.emplace_back(r, p);
    }
    std::sort(visible.begin(), visible.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    if (static_cast<int>(visible.size()) > c.max_points) visible.resize(c.max_points);
    rio::RadarFrame f;
    f.t = t - c.radar_delay;
    auto emit = [&](const coral::Vec3& p, double extra_vr) {
      const double r = p.norm(), az = std::atan2(p.y(), p.x()), el = std::asin(p.z() / r);
      const double rn = r + pn.sigma_range * N(rng), azn = az + pn.sigma_azimuth * N(rng),
                   eln = el + pn.sigma_elevation * N(rng);
      f.points.push_back(rn * coral::Vec3(std::cos(eln) * std::cos(azn),
                                          std::cos(eln) * std::sin(azn), std::sin(eln)));
      f.radial_velocity.push_back(-p.dot(v_radar) / r + extra_vr + c.sigma_doppler * N(rng));
      f.intensity.push_back(10.0);
    };
    for (const auto& [r, p] : visible) emit(p, 0.0);
    const int movers = static_cast<int>(std::round(c.outlier_fraction * visible.size()));
    for (int m = 0; m < movers; ++m) {
      const double r = 1.0 + (c.max_range - 1.0) * U(rng);
      const double az = c.half_fov_azimuth * (2 * U(rng) - 1);
      const double el = c.half_fov_elevation * (2 * U(rng) - 1);
      const double speed = (0.5 + 2.0 * U(rng)) * (U(rng) < 0.5 ? -1 : 1);
      emit(r * coral::Vec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)),
           speed);
    }
    seq.radar.push_back(std::move(f));
    if (c.radar_delay == 0.0) seq.ground_truth.push_back(kin.pose);
  }
  if (c.radar_delay != 0.0)
    for (const rio::ImuSample& s : seq.imu) seq.ground_truth.push_back(simulatedPose(c, s.t));
  if (c.barometer) simulateBarometer(c, &seq);
  return seq;
}

}  // namespace eval
}  // namespace coral_introspection
