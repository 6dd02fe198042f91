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
// The oblique errors of k tolerances (sweepErrors, `oblique`).
void addOblique(const coral::ToleranceConfig& tol, int dimension, double k,
                std::vector<SweepError>* out) {
  const double t = k * tol.translation, rot = k * tol.rotation_deg * M_PI / 180.0;
  const Eigen::Vector3d units[3] = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                                    Eigen::Vector3d::UnitZ()};
  const char* names[3] = {"x", "y", "z"};
  auto add = [&](const std::string& a, int s1, const std::string& b, int s2,
                 const Eigen::Vector3d& shift, double yaw, const std::string& mix) {
    SweepError e;
    e.axis_name = "oblique";
    e.sign = 1;
    e.multiple = k;
    e.magnitude = t;
    e.delta.translation() = shift;
    e.delta.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    std::ostringstream l;
    l << a << (s1 > 0 ? '+' : '-') << b << (s2 > 0 ? '+' : '-') << k << mix;
    e.label = l.str();
    out->push_back(e);
  };
  // Two translation axes: the error's direction at 45 deg between them (no suffix) and at
  // 22.5 and 67.5 deg ("@22.5"), |t| = k tolerances.
  const int planes[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (int p = 0; p < (dimension == 3 ? 3 : 1); ++p)
    for (double deg : {45.0, 22.5, 67.5})
      for (int s1 : {1, -1})
        for (int s2 : {1, -1}) {
          const double c = std::cos(deg * M_PI / 180.0), s = std::sin(deg * M_PI / 180.0);
          std::ostringstream mix;
          if (deg != 45.0) mix << "@" << deg;
          add(names[planes[p][0]], s1, names[planes[p][1]], s2,
              t * (s1 * c * units[planes[p][0]] + s2 * s * units[planes[p][1]]), 0.0, mix.str());
        }
  // x or y with yaw: both k tolerances (no suffix), or one of them half ("@1:0.5", "@0.5:1").
  for (int axis : {0, 1})
    for (const auto& [ts, ys] : {std::pair<double, double>{1, 1}, {1, 0.5}, {0.5, 1}})
      for (int s1 : {1, -1})
        for (int s2 : {1, -1}) {
          std::ostringstream mix;
          if (ts != ys) mix << "@" << ts << ":" << ys;
          add(names[axis], s1, "yaw", s2, s1 * ts * t * units[axis], s2 * ys * rot, mix.str());
        }
}
}  // namespace

std::vector<SweepError> sweepErrors(const coral::ToleranceConfig& tol, int dimension,
                                    const std::vector<double>& multiples,
                                    const std::vector<double>& yaw_degrees,
                                    const std::vector<TurnAxis>& turn_axes, bool oblique) {
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
  if (oblique)
    for (double k : multiples) addOblique(tol, dimension, k, &out);
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
