#include "coral_introspection/coral/tolerance.hpp"

#include <cmath>

#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace coral {

ToleranceConfig ToleranceConfig::lidar3d() { return ToleranceConfig(); }

ToleranceConfig ToleranceConfig::lidar2d() {
  ToleranceConfig c;
  c.rotation_deg = 5.0;
  return c;
}

ToleranceConfig ToleranceConfig::radar() {
  ToleranceConfig c;
  c.translation = 0.5;
  c.rotation_deg = 1.0;
  return c;
}

ToleranceConfig ToleranceConfig::forSensor(bool is_radar, int dimension) {
  return is_radar ? radar() : dimension == 2 ? lidar2d() : lidar3d();
}

std::string ToleranceConfig::validate() const {
  return Problems()
      .require(translation > 0.0 && translation <= 10.0, "translation", "in (0, 10] m", translation)
      .require(rotation_deg > 0.0 && rotation_deg <= 45.0, "rotation_deg", "in (0, 45] deg",
               rotation_deg)
      .str();
}

const char* axisName(Axis axis) {
  switch (axis) {
    case Axis::kX:
      return "x";
    case Axis::kY:
      return "y";
    case Axis::kZ:
      return "z";
    case Axis::kRoll:
      return "roll";
    case Axis::kPitch:
      return "pitch";
    default:
      return "yaw";
  }
}

bool isRotation(Axis axis) {
  return axis == Axis::kRoll || axis == Axis::kPitch || axis == Axis::kYaw;
}

std::vector<Axis> toleranceAxes(int dimension) {
  if (dimension == 2) return {Axis::kX, Axis::kY, Axis::kYaw};
  return {Axis::kX, Axis::kY, Axis::kZ, Axis::kRoll, Axis::kPitch, Axis::kYaw};
}

std::vector<ToleranceOffset> toleranceOffsets(const ToleranceConfig& tol, int dimension) {
  std::vector<ToleranceOffset> out;
  const double rot = tol.rotation_deg * M_PI / 180.0;
  for (Axis a : toleranceAxes(dimension))
    for (int sign : {1, -1}) {
      ToleranceOffset o;
      o.axis = a;
      o.sign = sign;
      o.name = std::string(axisName(a)) + (sign > 0 ? "+" : "-");
      const int i = static_cast<int>(a);
      if (isRotation(a))  // roll about x, pitch about y, yaw about z
        o.delta.linear() =
            Eigen::AngleAxisd(sign * rot, Eigen::Vector3d::Unit(i - 3)).toRotationMatrix();
      else
        o.delta.translation()[i] = sign * tol.translation;
      out.push_back(o);
    }
  return out;
}

}  // namespace coral
}  // namespace coral_introspection
