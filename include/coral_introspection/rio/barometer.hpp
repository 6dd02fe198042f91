// Barometer in the radar-inertial odometry: pressure -> height, and the two residuals that
// tie the window's heights to it.
//
// Height from pressure, standard atmosphere (ISA troposphere, 15 degC at sea level):
//   h(p) = 44330.8 m * (1 - (p / 101325 Pa)^0.190263).
// Only differences matter (a bias state absorbs the absolute offset); near 100 kPa one
// pascal is about 0.083 m.
//
// Measurement model per radar frame i: the n barometer samples of the interval before the
// frame, averaged to (h_i at time tau_i), read the body height plus a slowly varying bias
// b (weather, temperature drift, the flow around a hand-held device):
//   h_i = z(tau_i) + b_i + noise,   z(tau_i) ~ p_z,i + v_z,i (tau_i - t_i),
//   r_B = (p_z,i + v_z,i (tau_i - t_i) + b_i - h_i) / sigma_i,  sigma_i = sigma / sqrt(n).
// (The lever arm between barometer and IMU is left out: on a sensor board it is a few cm.)
// The bias is a random walk between consecutive frames i, j:
//   r_W = (b_j - b_i) / (q sqrt(t_j - t_i)),  q [m / sqrt(s)].
#pragma once

#include <ceres/sized_cost_function.h>

#include <string>

#include "coral_introspection/rio/types.hpp"

namespace coral_introspection {
namespace rio {

// One barometer reading: static pressure [Pa] at time t [s] (the IMU's clock).
struct BaroSample {
  double t = 0.0;
  double pressure = 0.0;
};

// Standard-atmosphere altitude [m] of a static pressure [Pa] (formula above).
double pressureToAltitude(double pressure);
// Its inverse: the pressure [Pa] at altitude h [m] (the simulator's barometer).
double altitudeToPressure(double h);

struct BarometerConfig {
  bool enabled = false;  // off: no barometer state or residual (the odometry without it)
  double sigma = 0.3;    // [m] noise of one height sample (white; a frame's mean: / sqrt(n))
  // [m / sqrt(s)] random walk of the bias between frames. Small: the bias must drift more
  // slowly than the odometry's height, or it absorbs the drift the barometer should remove.
  double bias_walk = 0.0005;
  std::string validate() const;
};

// r_B above over (pose, speed_bias, bias); tau_minus_t = tau_i - t_i.
class BaroFactor : public ceres::SizedCostFunction<1, 7, 9, 1> {
 public:
  BaroFactor(double height, double tau_minus_t, double sigma)
      : h_(height), dt_(tau_minus_t), inv_sigma_(1.0 / sigma) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  double h_, dt_, inv_sigma_;
};

// r_W above over (bias_i, bias_j); sigma = q sqrt(t_j - t_i).
class BaroBiasWalkFactor : public ceres::SizedCostFunction<1, 1, 1> {
 public:
  explicit BaroBiasWalkFactor(double sigma) : inv_sigma_(1.0 / sigma) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  double inv_sigma_;
};

}  // namespace rio
}  // namespace coral_introspection
