#include "coral_introspection/eval/error_sweep.hpp"

#include <cmath>
#include <sstream>

namespace coral_introspection {
namespace eval {

std::vector<SweepError> sweepErrors(const coral::ToleranceConfig& tol, int dimension,
                                    const std::vector<double>& multiples,
                                    const std::vector<double>& yaw_degrees) {
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
  for (double deg : yaw_degrees) {
    if (deg < tol.rotation_deg) continue;
    for (const coral::ToleranceOffset& o :
         coral::toleranceOffsets({tol.translation, deg}, dimension)) {
      if (o.axis != coral::Axis::kYaw || (deg >= 180.0 && o.sign < 0)) continue;  // +180 = -180
      SweepError e;
      e.axis = coral::Axis::kYaw;
      e.sign = o.sign;
      e.magnitude = deg;
      e.delta = o.delta;
      std::ostringstream s;
      s << o.name << deg << "deg";
      e.label = s.str();
      out.push_back(e);
    }
  }
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
    << (e.ground_truth ? "none" : coral::axisName(e.axis)) << ',' << e.multiple << ','
    << e.magnitude << ',' << e.ground_truth << ',' << v.valid << ',' << v.aligned << ','
    << v.probability << ',' << v.classifier.probability << ',' << v.relative.score << ','
    << v.relative.misaligned << ',' << v.coral.quality << ',' << v.coral.h_joint << ','
    << v.coral.h_sep << ',' << v.coral.overlap << ',' << v.coral.num_queries << ','
    << v.relative.flat_axes.size() << ',' << v.free_space.conflict << ',' << v.constraint.weakest
    << ',' << v.coarse.drop() << ',' << v.coarse.lowest.name << ',' << v.coarse.registered_size
    << ',' << preset_aligned;
  return s.str();
}

}  // namespace eval
}  // namespace coral_introspection
