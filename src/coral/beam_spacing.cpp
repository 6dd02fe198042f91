#include "coral_introspection/coral/beam_spacing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace coral_introspection {
namespace coral {

namespace {
// [deg] bearing about origin; false for a non-finite point or one on the origin.
bool bearingDeg(const Vec3& p, const Vec3& origin, double* deg) {
  if (!p.allFinite()) return false;
  const Vec3 d = p - origin;
  if (!(d.head<2>().squaredNorm() > 0.0)) return false;
  *deg = std::atan2(d.y(), d.x()) * 180.0 / M_PI;
  return true;
}
}  // namespace

namespace {
// The median step [deg] between sorted bearings, NaN when not a regular scan (the rule of
// medianBeamStepDeg). Sorts *bearings.
double medianStepOf(std::vector<double>* bearings) {
  std::sort(bearings->begin(), bearings->end());
  std::vector<double> steps;
  for (std::size_t i = 1; i < bearings->size(); ++i)
    if ((*bearings)[i] - (*bearings)[i - 1] > kMinBeamStepDeg)
      steps.push_back((*bearings)[i] - (*bearings)[i - 1]);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (steps.size() < 10) return nan;
  std::vector<double> sorted = steps;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double median = sorted[sorted.size() / 2];
  // A scan of beams steps by whole multiples of its spacing (gaps are beams without a return).
  // Points not about their sensor (a scan given in another frame, a merged cloud) do not: their
  // spacing is unknown, not the median of irregular steps.
  std::size_t regular = 0;
  for (const double s : steps) {
    const double ratio = s / median;
    regular += std::abs(ratio - std::round(ratio)) <= 0.1;
  }
  return regular >= steps.size() * 4 / 5 ? median : nan;
}

// Each point's bearing [deg] about origin, NaN for a point without one (bearingDeg false).
std::vector<double> bearingsOf(const Points& pts, const Vec3& origin) {
  std::vector<double> out(pts.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < pts.size(); ++i) bearingDeg(pts[i], origin, &out[i]);
  return out;
}

// The spacing of bearingsOf's result (its points without a bearing left out).
double medianStepOfBearings(const std::vector<double>& bearing) {
  std::vector<double> valid;
  valid.reserve(bearing.size());
  for (const double b : bearing)
    if (!std::isnan(b)) valid.push_back(b);
  return medianStepOf(&valid);
}
}  // namespace

double medianBeamStepDeg(const Points& pts, const Vec3& origin) {
  return medianStepOfBearings(bearingsOf(pts, origin));
}

const Points& thinToBeamStep(const Points& in, const Vec3& origin, double reference_step_deg,
                             Points* storage, std::size_t* dropped) {
  if (!(reference_step_deg > 0.0)) return in;
  // One bearing per point (atan2 once), for the spacing, the phase and the selection.
  const std::vector<double> bearing = bearingsOf(in, origin);
  const double step = medianStepOfBearings(bearing);
  if (!std::isfinite(step)) return in;
  const long k = std::lround(reference_step_deg / step);
  if (k < 2) return in;
  // The grid's phase: bearings lie at (n + phase) * step; the circular mean of their fractions
  // (a beam at exactly half a step must not flip between two indices by rounding noise).
  double s = 0.0, c = 0.0;
  for (const double deg : bearing) {  // in point order, as before the bearings were shared
    if (std::isnan(deg)) continue;
    const double f = 2.0 * M_PI * (deg / step);
    s += std::sin(f);
    c += std::cos(f);
  }
  const double phase = std::atan2(s, c) / (2.0 * M_PI);
  storage->clear();
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (std::isnan(bearing[i])) continue;  // unusable points are not beams: not kept
    const long n = std::lround(bearing[i] / step - phase);
    if (((n % k) + k) % k == 0) storage->push_back(in[i]);
  }
  *dropped += in.size() - storage->size();
  return *storage;
}

double beamSpacingShare(const Points& own, double reference_step_deg) {
  if (!(reference_step_deg > 0.0)) return 1.0;
  const double step = medianBeamStepDeg(own, Vec3::Zero());
  if (!std::isfinite(step)) return 1.0;  // too few to tell: counted as they are
  const double share = step / reference_step_deg;
  return std::abs(share - 1.0) < 0.1 ? 1.0 : share;
}

}  // namespace coral
}  // namespace coral_introspection
