// The beam spacing of a planar scan. The 2D presets' bounds count points (the constraint term)
// or read entropies of neighbourhoods whose point count depends on it (CorAl, the classifier),
// and they were chosen on scans of one spacing (lidar_2d: 180 beams of 1 deg). A scanner with
// another spacing sees the same walls with more or fewer points; these functions measure the
// spacing from the points alone (a PointCloud2 carries no beam geometry) and thin a denser scan
// to the reference spacing (doc/loop_closure.md, "Another beam spacing").
#pragma once

#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace coral {

constexpr double kMinBeamStepDeg = 1e-4;  // [deg] bearings closer than this are one beam

// The median step [deg] between the sorted bearings (about origin, in x-y) of the finite points
// off the origin: a planar scan's beam spacing, whatever gaps its no-returns leave. NaN for
// fewer than 10 steps (too few to tell) and when fewer than 80 % of the steps are whole
// multiples of it (within 0.1 of one): points that are not a scan about `origin` (given in
// another frame, merged from several scans) have no spacing to measure.
double medianBeamStepDeg(const Points& pts, const Vec3& origin);

// A planar scan finer than reference_step_deg thinned to it: with step = medianBeamStepDeg and
// k = round(reference_step_deg / step) >= 2, every k-th beam is kept, counted from the bearing
// grid's phase (the circular mean of bearing / step), so that a beam's fate depends on its
// bearing, not on which beams returned. The input itself (no copy) when k < 2, the step is
// unknown or reference_step_deg <= 0; otherwise the kept points in *storage (order kept).
// Adds the number dropped to *dropped.
const Points& thinToBeamStep(const Points& in, const Vec3& origin, double reference_step_deg,
                             Points* storage, std::size_t* dropped);

// The constraint term's share of a point (constraint.hpp): step / reference_step_deg, 1 within
// 10 % of the reference (a scanner of the reference spacing keeps its values exactly), for an
// unknown step and for reference_step_deg <= 0.
double beamSpacingShare(const Points& own, double reference_step_deg);

}  // namespace coral
}  // namespace coral_introspection
