#include "coral_introspection/eval/error_sweep.hpp"

#include <cmath>
#include <sstream>

namespace coral_introspection {
namespace core {

namespace {

Eigen::Isometry3d axisDelta(Axis axis, double amount) {
  Eigen::Isometry3d d = Eigen::Isometry3d::Identity();
  switch (axis) {
    case Axis::kX:
    case Axis::kY:
    case Axis::kZ:
      d.translation()[static_cast<int>(axis)] = amount;
      break;
    default:  // roll, pitch, yaw about x, y, z; amount in radians
      d.linear() = Eigen::AngleAxisd(amount, Eigen::Vector3d::Unit(static_cast<int>(axis) -
                                                                   static_cast<int>(Axis::kRoll)))
                       .toRotationMatrix();
  }
  return d;
}

}  // namespace

std::vector<SweepError> sweepErrors(const ToleranceConfig& tol, int dimension) {
  std::vector<SweepError> out;
  SweepError gt;
  gt.label = "ground truth";
  gt.ground_truth = true;
  out.push_back(gt);
  for (Axis axis : toleranceAxes(dimension))
    for (double k : sweepMultiples())
      for (int sign : {1, -1}) {
        SweepError e;
        e.axis = axis;
        e.sign = sign;
        e.multiple = k;
        const bool rot = isRotation(axis);
        e.magnitude = k * (rot ? tol.rotation_deg : tol.translation);
        e.delta = axisDelta(axis, sign * (rot ? e.magnitude * M_PI / 180.0 : e.magnitude));
        std::ostringstream s;
        s << axisName(axis) << (sign > 0 ? "+" : "-") << k;
        e.label = s.str();
        out.push_back(e);
      }
  for (double deg : sweepYawDegrees()) {
    if (deg < tol.rotation_deg) continue;
    for (int sign : {1, -1}) {
      if (deg >= 180.0 && sign < 0) continue;  // +180 = -180
      SweepError e;
      e.axis = Axis::kYaw;
      e.sign = sign;
      e.magnitude = deg;
      e.delta = axisDelta(Axis::kYaw, sign * deg * M_PI / 180.0);
      std::ostringstream s;
      s << "yaw" << (sign > 0 ? "+" : "-") << deg << "deg";
      e.label = s.str();
      out.push_back(e);
    }
  }
  return out;
}

std::string errorSweepCsvHeader() {
  return "dataset,pair,error,axis,multiple,magnitude,ground_truth,valid,aligned,probability,"
         "classifier_p,relative_score,relative_misaligned,q,h_joint,h_sep,overlap,num_queries";
}

std::string errorSweepCsvRow(const std::string& dataset, int pair, const SweepError& e,
                             const AlignmentVerdict& v) {
  std::ostringstream s;
  s.precision(6);
  s << dataset << ',' << pair << ',' << e.label << ','
    << (e.ground_truth ? "none" : axisName(e.axis)) << ',' << e.multiple << ',' << e.magnitude
    << ',' << e.ground_truth << ',' << v.valid << ',' << v.aligned << ',' << v.probability << ','
    << v.classifier.probability << ',' << v.relative.score << ',' << v.relative.misaligned << ','
    << v.coral.quality << ',' << v.coral.h_joint << ',' << v.coral.h_sep << ',' << v.coral.overlap
    << ',' << v.coral.num_queries;
  return s.str();
}

}  // namespace core
}  // namespace coral_introspection
