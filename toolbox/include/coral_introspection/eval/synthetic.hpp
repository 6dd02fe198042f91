// Ray-cast synthetic scenes with ground truth: the built-in demo pair, test fixtures and
// the simulated sequences of the nodelet tests. Planar rectangles give structure (walls,
// floor, boxes) whose misalignment CorAl must detect.
#pragma once

#include <optional>
#include <random>
#include <vector>

#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace eval {

struct Rect {
  coral::Vec3 center;
  coral::Vec3 half_u;  // half extent along the first in-plane axis
  coral::Vec3 half_v;  // half extent along the second (orthogonal to half_u)
};

struct SyntheticScene {
  std::vector<Rect> rects;
  // A 30 x 20 m yard: floor, four walls and boxes at several orientations so that every
  // horizontal translation and yaw is observable.
  static SyntheticScene structuredYard();
  // Range to the first surface hit along unit direction d from o, if any within max_range.
  std::optional<double> castRay(const coral::Vec3& o, const coral::Vec3& d, double max_range) const;
};

struct LidarModel {
  int azimuths = 720;                // horizontal rays per revolution
  int rings = 32;                    // 1 gives a planar (2D) scanner (32: ~1 deg spacing)
  double v_min_deg = -15.0;          // lowest ring elevation [deg]
  double v_max_deg = 15.0;           // highest ring elevation [deg]
  double min_range = 0.5;            // [m]
  double max_range = 40.0;           // [m]
  double range_noise = 0.01;         // [m] standard deviation along the ray
  bool random_azimuth_start = true;  // a new sampling of the scene on every scan
};

// Simulates one scan from sensor pose T_world_sensor; points are in the sensor frame.
coral::Points simulateScan(const SyntheticScene& scene, const Eigen::Isometry3d& T_world_sensor,
                           const LidarModel& model, std::mt19937& rng);

}  // namespace eval
}  // namespace coral_introspection
