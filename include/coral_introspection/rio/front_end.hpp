// Radar front end of the odometry: range / field-of-view / intensity filter, the polar
// covariance of every kept point (Sec. III-B), static points by Doppler consensus (RANSAC
// of Eq. 9 over the scan, radar::fitDoppler), and zero-velocity detection from Doppler.
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/rio/config.hpp"
#include "coral_introspection/rio/types.hpp"

namespace coral_introspection {
namespace rio {

struct RadarPoint {
  Vec3 p;          // radar frame
  double m = 0.0;  // sign-normalised Doppler: d^T v_radar for a static point
  Mat3 cov;        // Sigma_k (radar frame) under the configured uncertainty mode
};

struct FrontEndResult {
  std::vector<RadarPoint> points;  // kept points
  std::vector<int> static_points;  // indices into points: the Doppler consensus
  bool has_doppler = false;        // the frame carried radial velocities
  bool doppler_fit = false;        // the consensus fit succeeded
  Vec3 v_radar = Vec3::Zero();     // its ego velocity (radar frame) when doppler_fit
  bool standing = false;           // zero velocity detected
  std::size_t dropped = 0;         // points removed by the filter
};

// v_radar_predicted (optional): the IMU-predicted radar velocity, used to pick static
// points when the consensus fails (too few points, no majority).
FrontEndResult processRadarFrame(const RadarFrame& frame, const RioConfig& cfg,
                                 const Vec3* v_radar_predicted);

}  // namespace rio
}  // namespace coral_introspection
