// Every setting of the online introspection, with its default: one struct for the
// Introspector, embedded by the nodelet's NodeConfig (ROS parameters map onto it 1:1).
#pragma once

#include <string>

#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/coral/verdict.hpp"
#include "coral_introspection/online/pairing.hpp"
#include "coral_introspection/online/self_calibration.hpp"
#include "coral_introspection/radar/deskew.hpp"
#include "coral_introspection/radar/doppler.hpp"
#include "coral_introspection/radar/radar_uncertainty.hpp"

namespace coral_introspection {
namespace online {

// Doppler velocity check of 4D radar scans (radar/doppler.hpp): the odometry's velocity
// must explain the radial velocities of the static points.
struct DopplerCheckConfig {
  bool enabled = false;
  radar::DopplerConfig check;  // thresholds, confidence, sign convention, RANSAC seed
  // Weight each point by its propagated position covariance (Eq. 10-12) from the polar
  // noise model below. Without it the bearing noise is unmodelled and the check raises
  // about 3.5 % false alarms at confidence 0.99 instead of 1 % (doppler_eval --synthetic).
  bool point_covariances = true;
  // Polar measurement noise of the 4D radar. Default: an automotive 4D radar (ZF FRGen21
  // of View-of-Delft: 0.2 m range and 1.5 deg angular resolution read as 3 sigma).
  radar::RadarNoiseConfig noise = radar::RadarNoiseConfig::vodZfFrgen21();
  std::string validate() const;  // empty when valid
};

struct IntrospectorConfig {
  PairingConfig pairing;
  coral::CoralConfig coral;
  // classifier/ (betas, threshold, method, relative_margin, flat_ratio) and tolerance/: the
  // one verdict of coral/verdict.hpp, the same as coral_train evaluates.
  coral::VerdictConfig verdict;
  radar::DeskewConfig deskew;  // radar scans only (per-point stamps)
  DopplerCheckConfig doppler;
  // calibration/: online self-calibration of the classifier (self_calibration.hpp).
  SelfCalibrationConfig calibration;
  std::string validate() const;  // empty when valid; names the group (coral/, ...)
};

// "group/" before each "; "-separated message of a validate() result ("coral/radius must
// be > 0 m (got -1)"): messages name the parameter as the user writes it.
std::string prefixMessages(const std::string& group, const std::string& messages);

}  // namespace online
}  // namespace coral_introspection
