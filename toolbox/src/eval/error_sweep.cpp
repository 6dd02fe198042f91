#include "coral_introspection/eval/error_sweep.hpp"

#include <cmath>
#include <sstream>

namespace coral_introspection {
namespace eval {

const char* turnAxisName(TurnAxis axis) {
  switch (axis) {
    case TurnAxis::kRoll:
      return "roll";
    case TurnAxis::kPitch:
      return "pitch";
    case TurnAxis::kTilted:
      return "tilted";
    case TurnAxis::kYaw:
      break;
  }
  return "yaw";
}

bool parseTurnAxis(const std::string& name, TurnAxis* axis) {
  for (TurnAxis a : {TurnAxis::kYaw, TurnAxis::kRoll, TurnAxis::kPitch, TurnAxis::kTilted})
    if (name == turnAxisName(a)) {
      *axis = a;
      return true;
    }
  return false;
}

namespace {
// The fixed turns of `deg` about one axis, both signs (180 once): toleranceOffsets' rotation
// about z for yaw, about x / y for roll / pitch (same convention), and about (1, 1, 1).
void addTurns(TurnAxis turn, double deg, std::vector<SweepError>* out) {
  const Eigen::Vector3d axis = turn == TurnAxis::kYaw     ? Eigen::Vector3d::UnitZ()
                               : turn == TurnAxis::kRoll  ? Eigen::Vector3d::UnitX()
                               : turn == TurnAxis::kPitch ? Eigen::Vector3d::UnitY()
                                                          : Eigen::Vector3d(1, 1, 1).normalized();
  for (int sign : {1, -1}) {
    if (deg >= 180.0 && sign < 0) continue;  // +180 = -180
    SweepError e;
    e.axis = turn == TurnAxis::kRoll    ? coral::Axis::kRoll
             : turn == TurnAxis::kPitch ? coral::Axis::kPitch
                                        : coral::Axis::kYaw;
    if (turn == TurnAxis::kTilted) e.axis_name = turnAxisName(turn);
    e.sign = sign;
    e.magnitude = deg;
    e.delta.linear() = Eigen::AngleAxisd(sign * deg * M_PI / 180.0, axis).toRotationMatrix();
    std::ostringstream s;
    s << turnAxisName(turn) << (sign > 0 ? '+' : '-') << deg << "deg";
    e.label = s.str();
    out->push_back(e);
  }
}
}  // namespace

std::vector<SweepError> sweepErrors(const coral::ToleranceConfig& tol, int dimension,
                                    const std::vector<double>& multiples,
                                    const std::vector<double>& yaw_degrees,
                                    const std::vector<TurnAxis>& turn_axes) {
  std::vector<SweepError> out;
  SweepError gt;
  gt.label = "ground truth";
  gt.ground_truth = true;
  out.push_back(gt);
  // k tolerances: the relative check's offsets (tolerance.hpp) of a k times larger tolerance.
  for (double k : multiples)
    for (const coral::ToleranceOffset& o :
         coral::toleranceOffsets({k * tol.translation, k * tol.rotation_deg}, dimension)) {
      SweepError e;
      e.axis = o.axis;
      e.sign = o.sign;
      e.multiple = k;
      e.magnitude = k * (coral::isRotation(o.axis) ? tol.rotation_deg : tol.translation);
      e.delta = o.delta;
      std::ostringstream s;
      s << o.name << k;
      e.label = s.str();
      out.push_back(e);
    }
  for (TurnAxis turn : turn_axes)
    for (double deg : yaw_degrees)
      if (deg >= tol.rotation_deg && (turn == TurnAxis::kYaw || dimension == 3))
        addTurns(turn, deg, &out);
  return out;
}

std::string errorSweepCsvHeader() {
  return "dataset,pair,error,axis,multiple,magnitude,ground_truth,valid,aligned,probability,"
         "classifier_p,relative_score,relative_misaligned,q,h_joint,h_sep,overlap,num_queries,"
         "flat_axes,free_space,constraint,coarse_drop,coarse_step,registered_size,preset_aligned";
}

std::string errorSweepCsvRow(const std::string& dataset, int pair, const SweepError& e,
                             const coral::AlignmentVerdict& v, bool preset_aligned) {
  std::ostringstream s;
  s.precision(6);
  s << dataset << ',' << pair << ',' << e.label << ','
    << (e.ground_truth         ? "none"
        : !e.axis_name.empty() ? e.axis_name.c_str()
                               : coral::axisName(e.axis))
    << ',' << e.multiple << ',' << e.magnitude << ',' << e.ground_truth << ',' << v.valid << ','
    << v.aligned << ',' << v.probability << ',' << v.classifier.probability << ','
    << v.relative.score << ',' << v.relative.misaligned << ',' << v.coral.quality << ','
    << v.coral.h_joint << ',' << v.coral.h_sep << ',' << v.coral.overlap << ','
    << v.coral.num_queries << ',' << v.relative.flat_axes.size() << ',' << v.free_space.conflict
    << ',' << v.constraint.weakest << ',' << v.coarse.drop() << ',' << v.coarse.lowest.name << ','
    << v.coarse.registered_size << ',' << preset_aligned;
  return s.str();
}

}  // namespace eval
}  // namespace coral_introspection
