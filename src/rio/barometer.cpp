#include "coral_introspection/rio/barometer.hpp"

#include <cmath>

#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace rio {

namespace {
constexpr double kSeaLevelPressure = 101325.0;  // [Pa]
constexpr double kScaleHeight = 44330.8;        // [m] T0 / L of the ISA troposphere
constexpr double kExponent = 0.190263;          // R L / (g M)
}  // namespace

double pressureToAltitude(double pressure) {
  return kScaleHeight * (1.0 - std::pow(pressure / kSeaLevelPressure, kExponent));
}

double altitudeToPressure(double h) {
  return kSeaLevelPressure * std::pow(1.0 - h / kScaleHeight, 1.0 / kExponent);
}

std::string BarometerConfig::validate() const {
  return coral::Problems()
      .require(sigma > 0.0, "sigma", "> 0 m", sigma)
      .require(bias_walk > 0.0, "bias_walk", "> 0 m/sqrt(s)", bias_walk)
      .str();
}

bool BaroFactor::Evaluate(double const* const* parameters, double* residuals,
                          double** jacobians) const {
  const double pz = parameters[0][2], vz = parameters[1][2], b = parameters[2][0];
  residuals[0] = inv_sigma_ * (pz + vz * dt_ + b - h_);
  if (jacobians == nullptr) return true;
  if (jacobians[0]) {  // pose: only p_z (tangent dp = ambient dp, PoseManifold)
    for (int k = 0; k < 7; ++k) jacobians[0][k] = 0.0;
    jacobians[0][2] = inv_sigma_;
  }
  if (jacobians[1]) {  // speed_bias: only v_z
    for (int k = 0; k < 9; ++k) jacobians[1][k] = 0.0;
    jacobians[1][2] = inv_sigma_ * dt_;
  }
  if (jacobians[2]) jacobians[2][0] = inv_sigma_;
  return true;
}

bool BaroBiasWalkFactor::Evaluate(double const* const* parameters, double* residuals,
                                  double** jacobians) const {
  residuals[0] = inv_sigma_ * (parameters[1][0] - parameters[0][0]);
  if (jacobians == nullptr) return true;
  if (jacobians[0]) jacobians[0][0] = -inv_sigma_;
  if (jacobians[1]) jacobians[1][0] = inv_sigma_;
  return true;
}

}  // namespace rio
}  // namespace coral_introspection
