// Errors of every size a user meets, for judging a verdict beyond one tolerance: the later
// scan moved by 1, 2, 4 and 8 tolerances in both directions of each axis (toleranceAxes:
// translations by the translation tolerance, rotations by the rotation tolerance), and yaw
// errors of 5, 15, 45, 90 and 180 deg (and, on request, the same turns about roll, pitch and a
// tilted axis: "any rotation"), in b's sensor frame (T_a_b * delta, as training and
// the relative check). Errors past the CorAl radius are where a local test alone fails (Q
// falls again past the radius), so the sweep is what a verdict "for every error size" is
// tested and tuned on (coral_error_sweep, test_preset_verdicts).
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/coral/tolerance.hpp"
#include "coral_introspection/coral/verdict.hpp"

namespace coral_introspection {
namespace eval {

struct SweepError {
  std::string label;  // "ground truth", "x+1", "yaw-8", "yaw+90deg", "tilted-45deg", ...
  coral::Axis axis = coral::Axis::kX;
  std::string axis_name;      // the CSV's axis when it is none of coral::Axis ("tilted")
  int sign = 0;               // +1, -1 (0 at ground truth)
  double multiple = 0;        // of the tolerance (0 for the fixed yaw angles and ground truth)
  double magnitude = 0;       // [m] or [deg]
  bool ground_truth = false;  // true: the verdict must say aligned; else misaligned
  Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
};

// Multiples of the tolerance and the fixed yaw angles of the sweep.
inline const std::vector<double>& sweepMultiples() {
  static const std::vector<double> m = {1, 2, 4, 8};
  return m;
}
inline const std::vector<double>& sweepYawDegrees() {
  static const std::vector<double> d = {5, 15, 45, 90, 180};
  return d;
}

// Axes the fixed angles turn about. Yaw only by default (the tables of
// doc/verdict_every_error.md); in 3D also roll, pitch and the tilted axis (1, 1, 1) / sqrt(3),
// which turns all three at once: a sensor mount knocked askew, a scan handed over upside down.
enum class TurnAxis { kYaw, kRoll, kPitch, kTilted };
const char* turnAxisName(TurnAxis axis);  // "yaw", "roll", "pitch", "tilted"
bool parseTurnAxis(const std::string& name, TurnAxis* axis);
inline const std::vector<TurnAxis>& sweepTurnAxes() {
  static const std::vector<TurnAxis> a = {TurnAxis::kYaw};
  return a;
}

// Ground truth first, then every axis x multiple x sign, then the fixed angles about each turn
// axis (both signs; 180 deg once). Fixed angles below the rotation tolerance are left out
// (they are not errors at that tolerance). Turn axes other than yaw need dimension 3 (a 2D
// scan has no roll or pitch): in 2D they are left out.
// oblique: also, per multiple k, errors between the axes (axis_name "oblique"), each of size k
// (coral::toleranceSize): k tolerances between two translation axes, at 45 deg ("x+y-2": both
// components k t / sqrt(2)) and at 22.5 and 67.5 deg ("x+y-2@22.5"; x-y in 2D, also x-z and y-z
// in 3D), and x or y with yaw, both at k tolerances ("x-yaw+1") or one of them at half
// ("x-yaw+1@1:0.5", "@0.5:1"). A registration rarely errs along one axis, and the relative
// check probes one axis at a time: a probe along x removes only part of such an error. The
// shapes without a suffix were measured first; those with "@" tell whether a remedy chosen on
// them holds for other mixes (doc/verdict_every_error.md "Errors between the axes").
std::vector<SweepError> sweepErrors(const coral::ToleranceConfig& tol, int dimension,
                                    const std::vector<double>& multiples = sweepMultiples(),
                                    const std::vector<double>& yaw_degrees = sweepYawDegrees(),
                                    const std::vector<TurnAxis>& turn_axes = sweepTurnAxes(),
                                    bool oblique = false);

// One CSV line per judged error: the terms behind the verdict, `aligned` as method `both`
// combines them (v: judged with kBoth, measure_gate_terms) and, last, `preset_aligned`: the
// preset's own verdict (its method and gate, the one coral_error_sweep's summary counts).
std::string errorSweepCsvHeader();
std::string errorSweepCsvRow(const std::string& dataset, int pair, const SweepError& e,
                             const coral::AlignmentVerdict& v, bool preset_aligned);

}  // namespace eval
}  // namespace coral_introspection
