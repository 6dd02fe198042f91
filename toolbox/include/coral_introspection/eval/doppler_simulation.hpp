// Simulated Doppler radar scans with ground-truth sensor velocity, moving-object outliers
// and polar measurement noise: fixtures for the Doppler tests and the doppler_eval tool.
#pragma once

#include <random>
#include <vector>

#include "coral_introspection/coral/types.hpp"
#include "coral_introspection/radar/radar_uncertainty.hpp"

namespace coral_introspection {
namespace eval {

struct DopplerSimConfig {
  int num_points = 60;
  double outlier_fraction = 0.3;     // share of points on moving objects
  double min_range = 1.0;            // [m]
  double max_range = 20.0;           // [m]
  double azimuth_half_fov = 1.05;    // [rad] points within +- this azimuth
  double elevation_half_fov = 0.26;  // [rad]; 0 gives a planar (z = 0) scan
  // Polar noise on the measured positions (the bearing used for Eq. 9 is noisy too).
  radar::RadarNoiseConfig position_noise{0.05, 0.0175, 0.035};
  double sigma_doppler = 0.05;   // [m/s] Gaussian noise on v_r
  double mover_min_speed = 0.5;  // [m/s] |extra radial velocity| of a moving point
  double mover_max_speed = 3.0;  // [m/s]
  bool radial_velocity_positive_away = true;
};

struct DopplerSimScan {
  coral::Points points;                 // measured positions, sensor frame
  std::vector<double> radial_velocity;  // measured v_r [m/s]
  std::vector<bool> is_static;
};

// One scan seen by a sensor moving with v_sensor (sensor frame).
DopplerSimScan simulateDopplerScan(const coral::Vec3& v_sensor, const DopplerSimConfig& cfg,
                                   std::mt19937& rng);

}  // namespace eval
}  // namespace coral_introspection
