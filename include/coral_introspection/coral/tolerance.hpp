// The alignment error that matters to the user: a pair is "misaligned" when its relative
// pose is off by at least the tolerance in translation or in rotation. Training induces
// misalignments of exactly this size, and the relative check (relative_check.hpp) probes Q
// one tolerance away along each axis. Offsets act in the sensor frame of the later scan b
// (T_a_b' = T_a_b * Delta), as in the paper's self-supervised training (Sec. III-F).
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace coral_introspection {
namespace coral {

// Defaults: 3D lidar. The rotation tolerance is the angle that moves a point at the typical
// range of the sensor's structure by the translation tolerance (d * theta = t), so that
// both describe an error of the same size: 3D lidar structure at about 10 m (median point
// range of the shared Livox keyframes) gives 0.3 m / 10 m = 1.7 deg -> 2 deg.
struct ToleranceConfig {
  double translation = 0.3;   // [m] along x, y (and z in 3D)
  double rotation_deg = 2.0;  // [deg] about yaw (and roll, pitch in 3D)

  static ToleranceConfig lidar3d();  // the defaults above
  // 2D lidar indoors: walls at 2-5 m (median range 2.4 m on the ACES log): 0.3 m, 5 deg.
  static ToleranceConfig lidar2d();
  // Spinning radar: 0.5 m (the paper's middle error, Table II); RIP features lie at
  // 20-60 m, so 0.5 m / 30 m = 1 deg.
  static ToleranceConfig radar();
  // The default of a sensor class: radar, else 2D or 3D lidar by the CorAl dimension.
  static ToleranceConfig forSensor(bool radar, int dimension);
  std::string validate() const;  // empty when valid
};

enum class Axis { kX, kY, kZ, kRoll, kPitch, kYaw };
const char* axisName(Axis axis);  // "x", "y", "z", "roll", "pitch", "yaw"
bool isRotation(Axis axis);

// One tolerance step along one axis and direction, in b's sensor frame.
struct ToleranceOffset {
  Axis axis = Axis::kX;
  int sign = 1;                                             // +1 or -1
  std::string name;                                         // "x+", "yaw-", ...
  Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();  // Delta of T_a_b * Delta
};

// Axes probed for a CorAl dimension: x, y, yaw (2) or x, y, z, roll, pitch, yaw (3).
std::vector<Axis> toleranceAxes(int dimension);

// Both signs of every axis of toleranceAxes(dimension), axis by axis ("x+", "x-", ...).
std::vector<ToleranceOffset> toleranceOffsets(const ToleranceConfig& tol, int dimension);

}  // namespace coral
}  // namespace coral_introspection
