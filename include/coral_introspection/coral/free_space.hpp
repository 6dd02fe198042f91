// Free-space consistency of a registered pair: every return of a scan says that the space
// between its sensor and the return is empty. Under the right relative pose, points of one
// scan do not lie in the space the other scan saw through; under a wrong one that aligns
// two look-alike places (a false loop closure that ICP converged on, a corridor slid by a
// metre), walls, corridor ends and door frames of one scan land where the other looked
// through to something farther away. CorAl (Eq. 5) only scores where points are; this
// scores where they cannot be, from the same two clouds and their sensor origins.
#pragma once

#include <limits>
#include <string>

#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace coral {

struct FreeSpaceConfig {
  // [deg] angular bin of the range images (azimuth; elevation too in 3D). Coarser than the
  // scanner's resolution so that a seen surface leaves no empty bins: 1 deg covers 2D laser
  // scanners (0.25-1 deg) and 64-beam lidars (0.4 deg vertical); a planar scan of coarser beam
  // spacing (medianBeamStepDeg) gets bins of 1.1 of its steps; a point is tested against
  // the nearest return of its bin and both neighbours (3 x 3 in 3D), which also absorbs
  // grazing surfaces and depth edges.
  double bin_deg = 1.0;
  // [m] a point conflicts when it lies at least this much in front of that nearest return;
  // conflicts closer than this to each other (or in touching bins) form one group.
  double margin = 0.5;
  // [m] only groups of conflicts (in touching bins) at least this wide (horizontal extent of
  // their points) count: people and
  // other things that moved between the scans stand in each other's free space as small
  // groups (on the ACES log they made most of the conflicts of true loop closures); a
  // corridor end or a wall of a wrong match is wider. 0 = every conflict counts.
  double min_extent = 1.0;
  // Fewer tested points than this (in both directions together): no result.
  int min_tested = 20;
  std::string validate() const;  // empty when valid
};

struct FreeSpaceResult {
  bool valid = false;
  // Fraction of tested points lying in the other scan's free space, the larger of the two
  // directions (a's points in b's view, b's points in a's view) [-].
  double conflict = std::numeric_limits<double>::quiet_NaN();
  int tested = 0;     // points whose direction the other scan observed (both directions)
  int conflicts = 0;  // of those, in front of the other scan's return by >= margin, in groups
                      // at least min_extent wide
};

// a and b each in their own sensor frame (origin = the sensor, Scan::origin), b moved into
// a's frame by T_a_b. dimension 2: planar (x, y; azimuth bins only). Never throws; NaN
// points are skipped. Precondition: cfg.validate() is empty.
FreeSpaceResult freeSpaceConflict(const Points& a, const Vec3& origin_a, const Points& b,
                                  const Vec3& origin_b, const Eigen::Isometry3d& T_a_b,
                                  int dimension, const FreeSpaceConfig& cfg);

}  // namespace coral
}  // namespace coral_introspection
