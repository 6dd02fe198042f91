// How firmly a registered pair pins its own relative pose down: the weakest direction of the
// registration's information over the surfaces both scans see. CorAl (Eq. 5) and the
// free-space term (free_space.hpp) score whether the pose is consistent; a pair whose shared
// structure is a corridor's two walls, a short piece of wall or a few posts is consistent
// at every pose along the corridor or about the piece, and a registration may have stopped
// anywhere there. Loop-closure candidates are such pairs more often than consecutive scans
// (other viewpoint, little overlap): accepting one adds an edge the map cannot check. This
// is the degeneracy measure of Zhang, Kaess and Singh ("On degeneracy of optimization-based
// state estimation problems", ICRA 2016): the smallest eigenvalue of J^T J of point-to-line
// (2D) or point-to-plane (3D) residuals, here in tolerance units so that one number fits
// translation and rotation.
#pragma once

#include <limits>

#include "coral_introspection/coral/beam_spacing.hpp"
#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/coral/tolerance.hpp"
#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace coral {

struct ConstraintResult {
  bool valid = false;  // measured (a pair CorAl could judge)
  // Over the error directions of one tolerance (translation / tolerance and rotation /
  // rotation tolerance combined to length 1), the smallest sum of the squared displacements
  // of the shared surface points along their normals, in tolerances^2: "in effect this many
  // shared surface points move by a full tolerance under the weakest error of one
  // tolerance". The smaller of the two scans' values. 0 when nothing is shared.
  double weakest = std::numeric_limits<double>::quiet_NaN();
  int points = 0;  // shared surface points used (both scans)
};

// The least direction of a neighbourhood's covariance (its surface normal: a line's in 2D,
// dimension 2 reads the x-y block, a plane's in 3D) and how line- or plane-like it is,
// weight = 1 - lambda_min / lambda_mid in [0, 1]. False when the neighbourhood is not even a
// line (lambda_mid <= 0). *spread (optional): lambda_mid / lambda_max in 3D, how far the
// neighbourhood is from a line (1 in 2D). Also the normals of the restart check's
// registration.
bool surfaceNormal(const Eigen::Matrix3d& cov, int dimension, Vec3* normal, double* weight,
                   double* spread = nullptr);

// The term counts points: a 2D scanner with twice the beams per degree sees twice the points
// on the same wall and would pass a bound chosen on the other at half the geometry (lidar_2d's
// was chosen on 180-beam scans of 1 deg spacing: Intel, ACES). Each point then counts by its
// share (beamSpacingShare, beam_spacing.hpp).

// a and b each in their own sensor frame, b moved into a's frame by T_a_b (as
// freeSpaceConflict takes them). A point is shared when it has
// coral.min_neighbours points of its own scan and coral.min_neighbours_other of the other
// within coral.maxRadius() (CorAl's overlap); its normal is the least direction of its own
// neighbourhood's covariance, weighted by how line-like (2D) or plane-like (3D) that is
// (1 - lambda_min / lambda_mid), so that corners and clutter pin less than walls. Rotation
// is about the centroid of the shared points. dimension 2: x, y, yaw (3 x 3); 3: 6 x 6. At
// most kMaxQueries points per scan are used (a deterministic stride): bounded work on dense
// 3D clouds. 2D with reference_beam_step_deg > 0: each scan's value is multiplied by
// beamSpacingShare(its points), so that it is in points at that beam spacing whatever the
// scanner (0: points as they are). Never throws; non-finite points are skipped.
ConstraintResult registrationConstraint(const Points& a, const Points& b,
                                        const Eigen::Isometry3d& T_a_b, const CoralConfig& coral,
                                        const ToleranceConfig& tolerance,
                                        double reference_beam_step_deg = 0.0);

}  // namespace coral
}  // namespace coral_introspection
