// Radar-IMU time offset estimated online, as VINS-Mono does for the camera-IMU offset
// (Qin and Shen, "Online Temporal Calibration for Monocular Visual-Inertial Systems", 2018):
// one scalar state t_d, the radar measurement time on the IMU clock minus the radar stamp
// (radar_time_offset is its prior). A frame is placed at stamp + t_d,ref (the estimate when
// it arrived); a measurement taken at stamp + t_d is moved to the frame time to first order
// with its rate of change, held constant during a solve:
//   r(x, t_d) = r(x) + (t_d - t_d,ref) c,   c = W dz/dt  (W: the residual's whitening).
// The paper's residuals (radar_point_uncertainty_slam, Eq. 9 and Eq. 15) keep their
// Jacobians; the one with respect to t_d is c.
//
// The bound is also judged at arrival: the newest IMU stamp when a radar frame arrives, minus
// the frame's time, is the radar's latency plus the clock offset; it cannot be below -max_abs
// (a latency is not negative) and should not be above max_latency + max_abs.
//
// Rates in the radar frame (coordinates of a frame turning with the radar, rate omega_r):
// - a static point p_k (Eq. 15's measurement): dp_k/dt = -(omega_r x p_k + v_r);
// - the Doppler d^T v_r of a static point along the bearing d (Eq. 9, d measured at the
//   same instant): d^T dv_r/dt, with dv_r/dt = R_E^T (f - b_a + R_i^T g - (omega - b_g) x v_b
//   + alpha x t_E), v_b = R_i^T v_i the body velocity, f the specific force, alpha the angular
//   acceleration and g = (0, 0, -gravity) the gravity vector.
#pragma once

#include <ceres/cost_function.h>
#include <ceres/sized_cost_function.h>

#include <memory>
#include <string>
#include <vector>

#include "coral_introspection/rio/radar_factors.hpp"
#include "coral_introspection/rio/types.hpp"

namespace coral_introspection {
namespace rio {

struct TimeOffsetConfig {
  // Off: t_d = radar_time_offset, fixed (no state, no arrival check: the odometry of earlier
  // versions, byte for byte). Off by default: t_d needs rotation to be observed (on the
  // simulated vehicle drive it is not), and the arrival check needs the arrival order.
  bool estimate = false;
  double sigma = 0.01;  // [s] prior sigma of t_d around radar_time_offset
  // [s] bound of |t_d|. An offset the first-order shift cannot explain (a 0.1 s shift turns a
  // hand-held radar by up to 15 deg) is not estimated but refused (max_time_at_bound).
  double max_abs = 0.1;
  // [s] of tracked frames with t_d at its bound after which the input is refused: the clocks
  // differ by more than the bound.
  double max_time_at_bound = 1.0;
  // [s] longest plausible delay from a radar frame's time to its arrival (driver, transport).
  // Radar frames that arrive, on the IMU's clock, earlier than -max_abs or later than
  // max_latency + max_abs after their time (median of 20 frames) are refused: no t_d within
  // the bound explains that. (TI bag: 0.12 s.)
  double max_latency = 0.3;
  std::string validate() const;
};

// dp_k/dt above: the apparent velocity of a static point in the radar frame.
Vec3 staticPointRate(const Vec3& p, const Vec3& omega_radar, const Vec3& v_radar);

// dv_r/dt above (radar frame); omega, f: the raw gyro rate and specific force at the frame.
Vec3 radarAcceleration(const NavState& s, const Vec3& omega, const Vec3& alpha, const Vec3& f,
                       const Extrinsics& ext, double gravity);

// alpha at the end of an IMU interval: the least-squares slope of the gyro rate over its
// samples of the last `span` seconds (zero with fewer than 3).
Vec3 angularAcceleration(const std::vector<ImuSample>& interval, double span);

// r(x, t_d) above around a residual `base` (any parameter blocks); t_d is one more block of
// size 1, appended. rate: c (whitened like the base residual).
class TimeShiftedFactor : public ceres::CostFunction {
 public:
  TimeShiftedFactor(std::shared_ptr<const ceres::CostFunction> base, const Eigen::VectorXd& rate,
                    double td_ref);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;
  const ceres::CostFunction& base() const { return *base_; }

 private:
  std::shared_ptr<const ceres::CostFunction> base_;
  Eigen::VectorXd rate_;
  double td_ref_;
};

// Prior of t_d: (t_d - mean) / sigma.
class TimeOffsetPrior : public ceres::SizedCostFunction<1, 1> {
 public:
  TimeOffsetPrior(double mean, double sigma) : mean_(mean), inv_sigma_(1.0 / sigma) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  double mean_, inv_sigma_;
};

}  // namespace rio
}  // namespace coral_introspection
