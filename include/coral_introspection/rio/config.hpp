// Every setting of the radar-inertial odometry, with its default (the one source of
// defaults of the rio module; YAML presets list only what differs).
#pragma once

#include <string>

#include "coral_introspection/radar/doppler.hpp"
#include "coral_introspection/radar/radar_uncertainty.hpp"
#include "coral_introspection/rio/barometer.hpp"
#include "coral_introspection/rio/preintegration.hpp"
#include "coral_introspection/rio/radar_factors.hpp"
#include "coral_introspection/rio/time_offset.hpp"

namespace coral_introspection {
namespace rio {

// Which parts of the polar point-uncertainty model (Sec. III-B) the residuals and the
// association use: the paper's ablation (Table I).
enum class UncertaintyMode {
  kFull,       // Sigma_k = A diag(sigma_r^2, Sigma_Omega) A^T (the paper's system)
  kNone,       // isotropic Cartesian sigma, constant Doppler weight, Euclidean gate
  kNoRange,    // without the range part (sigma_r; how: UncertaintyConfig::ablation_replace)
  kNoBearing,  // without the bearing part (Sigma_Omega; idem)
};

struct UncertaintyConfig {
  UncertaintyMode mode = UncertaintyMode::kFull;
  // Polar noise. Default: a TI-class single-chip radar as the authors set it for
  // ColoRadar (sigma_r 0.105 m, sigma_azimuth 0.0089 rad, sigma_elevation 0.0088 rad).
  radar::RadarNoiseConfig noise{0.105, 0.0089, 0.0088};
  double covariance_scale = 1.0;  // Sigma <- scale * Sigma (Table II: 2^alpha)
  double isotropic_sigma = 0.1;   // [m] used where the model is switched off
  // How kNoRange / kNoBearing remove their part. false (the paper, Sec. IV-B: "setting sigma_r
  // or Sigma_Omega to a very small value"): that sigma times ablation_shrink, in the
  // association gate and in every residual weight; true: that part replaced by
  // isotropic_sigma (a variant of this package, not the paper's).
  bool ablation_replace = false;
  double ablation_shrink = 1e-3;
  double sigma_doppler = 0.05;  // [m/s] Doppler noise floor added to every Doppler variance
  double doppler_sigma_isotropic = 0.1;  // [m/s] Doppler sigma of the kNone mode
  double min_variance = 1e-6;            // [m^2] eigenvalue floor of Sigma_k
  std::string validate() const;
};

struct FrontEndConfig {
  double min_range = 0.25;       // [m]
  double max_range = 100.0;      // [m]
  double max_azimuth = 1.57;     // [rad] |azimuth| in the radar frame
  double max_elevation = 1.57;   // [rad] |elevation|
  double min_intensity = -1e9;   // points below are dropped (when intensity is given)
  radar::DopplerConfig doppler;  // RANSAC consensus of the static points
  // Fallback when the consensus fails: static = |m - d^T v_predicted| below this [m/s].
  double static_threshold = 0.3;
  // Standing radar: zero velocity consistent with the Doppler fit (chi-square test) and
  // the fitted speed below this [m/s].
  double zero_velocity_speed = 0.15;
  int zero_velocity_min_points = 5;  // static points needed to call a frame standing
  bool radial_velocity_positive_away = true;
  std::string validate() const;
};

struct AssociationConfig {
  double gate_sigma = 3.0;         // Mahalanobis gate (3-sigma rule, Sec. III-D)
  double max_search_radius = 1.0;  // [m] Euclidean cap of the candidate search
  int min_observations = 4;        // a track becomes a landmark with this many
  int max_map_landmarks = 3000;    // landmarks kept after leaving the window
  bool map_landmarks = false;      // match against (fixed) landmarks that left the window
  double outlier_chi2 = 16.27;     // whitened squared point residual (3 dof, 99.9%) dropped
  std::string validate() const;
};

struct SolverConfig {
  int window_size = 6;  // frames kept after a solve (the newest is added on top)
  int max_iterations = 10;
  double max_solver_time = 0.05;  // [s] per frame
  std::string loss = "cauchy";    // robust loss of radar residuals: none | huber | cauchy
  double loss_scale = 1.0;        // of the whitened residual
  bool use_doppler = true;        // Doppler residuals (Sec. III-C)
  bool use_points = true;         // point-to-landmark residuals (Sec. III-E)
  bool marginalize = true;        // false: hold the oldest state constant (authors' code)
  std::string validate() const;
};

struct InitConfig {
  double static_duration = 1.0;    // [s] of standing data before the odometry starts
  double max_gyro_std = 0.02;      // [rad/s] IMU at rest: per-axis std of the rate below
  double max_acc_std = 0.3;        // [m/s^2] and of the specific force below
  double timeout = 5.0;            // [s] start anyway (moving start) after this long
  double sigma_roll_pitch = 0.01;  // [rad] prior of the first state
  double sigma_yaw = 1e-4, sigma_position = 1e-4;  // gauge: first pose fixed
  double sigma_velocity = 0.01;                    // [m/s] standing start
  double sigma_acc_bias = 0.05, sigma_gyro_bias = 0.002;
  std::string validate() const;
};

struct ZeroVelocityConfig {
  bool enabled = true;
  double sigma_velocity = 0.005;  // [m/s] of v_i = 0 on a standing frame
  // Gyro bias from a standing interval when the rate's per-axis std is below max_gyro_std
  // and its mean differs from the current bias estimate by less than max_gyro_rate (a
  // standing radar may still turn about itself).
  double max_gyro_std = 0.006;   // [rad/s]
  double max_gyro_rate = 0.005;  // [rad/s]
  double min_gyro_samples = 10;
  std::string validate() const;
};

struct HealthConfig {
  double max_speed = 20.0;      // [m/s]
  double max_acc_bias = 1.0;    // [m/s^2]
  double max_gyro_bias = 0.2;   // [rad/s]
  double max_correction = 1.0;  // [m] solved newest position vs IMU prediction
  double max_imu_gap = 0.1;     // [s] larger gaps reset the window
  std::string validate() const;
};

struct RioConfig {
  ImuNoiseConfig imu;
  Extrinsics extrinsics;  // radar pose in the body (IMU) frame
  // [s] added to every radar stamp: the radar measurement time on the IMU clock minus the
  // stamp; with time_offset/estimate the prior of the estimate (time_offset.hpp).
  double radar_time_offset = 0.0;
  TimeOffsetConfig time_offset;
  UncertaintyConfig uncertainty;
  FrontEndConfig front_end;
  AssociationConfig association;
  SolverConfig solver;
  InitConfig init;
  ZeroVelocityConfig zero_velocity;
  HealthConfig health;
  BarometerConfig barometer;     // height from pressure with a random-walk bias (barometer.hpp)
  std::string validate() const;  // empty when valid
};

}  // namespace rio
}  // namespace coral_introspection
