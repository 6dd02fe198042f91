// One radar frame inside the estimator's window (private to estimator*.cpp).
#pragma once

#include <memory>
#include <vector>

#include "coral_introspection/rio/estimator.hpp"
#include "coral_introspection/rio/preintegration.hpp"

namespace coral_introspection {
namespace rio {

struct Estimator::WindowFrame {
  long id = 0;
  double t = 0.0;
  StateBlocks x;                        // the Ceres parameter blocks
  std::unique_ptr<Preintegration> pre;  // previous frame -> this one (null for the first)
  Vec3 omega = Vec3::Zero();            // raw gyro rate at t (lever arm of Eq. 9)
  Vec3 acc = Vec3::Zero();              // raw specific force at t (time offset: the Doppler's rate)
  Vec3 alpha = Vec3::Zero();            // [rad/s^2] angular acceleration at t (idem)
  std::vector<RadarPoint> static_points;  // Doppler residuals (Sec. III-C)
  bool standing = false;                  // Doppler: zero velocity
  bool gyro_still = false;                // standing and the IMU did not rotate
  Vec3 gyro_mean = Vec3::Zero();          // mean raw rate of the interval before t
  double gyro_sigma = 0.0;                // [rad/s] of gyro_mean as a bias measurement
  // Barometer (barometer.hpp). The bias block exists from the first frame with a reading
  // on (then every later frame has one, tied by the random walk) until a reset.
  bool has_baro_bias = false;
  double baro_bias[1] = {0.0};  // [m] barometer height minus body height
  bool has_baro = false;        // a residual: mean height of the samples before t
  double baro_height = 0.0, baro_dt = 0.0, baro_sigma = 1.0;  // h_i, tau_i - t_i, sigma_i

  NavState state() const {
    NavState s;
    fromBlocks(x, &s);
    s.t = t;
    return s;
  }
};

}  // namespace rio
}  // namespace coral_introspection
