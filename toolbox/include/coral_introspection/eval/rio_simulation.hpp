// A 4D radar + IMU simulator with ground truth for the odometry: static reflectors around
// a hand-held loop (a room, TI-like radar) or a vehicle loop (a figure eight through a
// scattered outdoor scene, automotive radar); radar points with polar noise (range,
// azimuth, elevation: the paper's model, Sec. III-B) and Doppler noise, moving-object
// outliers and missed detections; IMU samples with white noise and bias random walks.
// Both loops start and end at rest, at the same pose. Optionally a barometer: the true
// height plus a random-walk bias and white noise, as static pressure (standard atmosphere).
#pragma once

#include <string>

#include "coral_introspection/eval/rio_sequence.hpp"
#include "coral_introspection/radar/radar_uncertainty.hpp"
#include "coral_introspection/rio/preintegration.hpp"
#include "coral_introspection/rio/radar_factors.hpp"

namespace coral_introspection {
namespace eval {

enum class SimTrajectory { kHandheld, kVehicle };

struct RioSimConfig {
  SimTrajectory trajectory = SimTrajectory::kHandheld;
  double duration = 40.0;     // [s]
  double static_start = 5.0;  // [s] at rest before the motion
  double static_end = 5.0;    // [s] at rest after it
  double imu_rate = 200.0;    // [Hz]
  double radar_rate = 10.0;   // [Hz]
  rio::ImuNoiseConfig imu_noise{0.002, 0.0002, 0.0005, 0.00002, 9.81};  // true densities
  rio::Vec3 acc_bias = rio::Vec3(0.05, -0.03, 0.08);                    // [m/s^2] initial
  rio::Vec3 gyro_bias = rio::Vec3(0.002, -0.001, 0.003);                // [rad/s] initial
  rio::Extrinsics extrinsics;                                           // radar in the body frame
  radar::RadarNoiseConfig point_noise{0.04, 0.03, 0.03};                // true polar noise
  double sigma_doppler = 0.03;                                          // [m/s]
  double max_range = 10.0;                                              // [m]
  double half_fov_azimuth = 1.05, half_fov_elevation = 0.35;            // [rad]
  double detection_probability = 0.8;
  int max_points = 80;             // strongest (closest) detections kept per frame
  double outlier_fraction = 0.05;  // of the points: movers (random Doppler) at random places
  int num_reflectors = 500;
  // Barometer (off: no samples, and the random draws of the other sensors are unchanged).
  bool barometer = false;
  double baro_rate = 50.0;         // [Hz] (the TI recording's: 51 Hz)
  double baro_sigma = 0.3;         // [m] white noise of one sample
  double baro_bias = 0.4;          // [m] initial bias (reading minus true height)
  double baro_bias_walk = 0.0005;  // [m / sqrt(s)]
  double site_altitude = 300.0;    // [m] of the world origin (sets the pressure level)
  // [s] radar-IMU time offset: each radar frame is stamped this much before its measurement
  // time (the estimator's t_d is then +radar_delay). With a delay the ground truth is given
  // at every IMU sample (the odometry's frame times then differ from the measurement times).
  double radar_delay = 0.0;
  unsigned seed = 1;

  // The two sequences of the evaluation (doc/rio.md): TI-like hand-held loop in a room,
  // automotive-like vehicle loop.
  static RioSimConfig handheld(unsigned seed);
  static RioSimConfig vehicle(unsigned seed);
};

// The body pose at time t of the configured trajectory (ground truth).
StampedPose simulatedPose(const RioSimConfig& cfg, double t);

RioSequence simulateRio(const RioSimConfig& cfg);

}  // namespace eval
}  // namespace coral_introspection
