// NDT point-to-distribution alignment score and Rel-NDT (paper Sec. IV-1 d, e; Eq. 11):
// a voxel grid of Gaussians over P_a, and the mean density of P_b's points under it.
#pragma once

#include <string>

#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace eval {

struct NdtConfig {
  int dimension = 3;        // 2 (radar) or 3
  double voxel_size = 0.6;  // [m] v = 2 r (Sec. IV: 2 x the CorAl radius 0.3 m)
  int min_points = 5;       // points a voxel needs to hold a Gaussian (>= dimension + 1)
  // Eigenvalues below this fraction of the largest are raised to it (Magnusson's 3D-NDT),
  // so flat cells (walls, radar lines) keep a finite density and entropy.
  double eigen_floor_ratio = 0.01;
  std::string validate() const;  // empty when valid
};

struct NdtResult {
  bool valid = false;           // at least one overlapping point
  double score = 0.0;           // s of Eq. 11: mean pdf of the nearest overlapping cell
  double entropy = 0.0;         // Rel-NDT: mean differential entropy (Eq. 1) of those cells [nats]
  std::size_t num_cells = 0;    // Gaussian cells built from P_a
  std::size_t num_overlap = 0;  // n of Eq. 11
  std::size_t num_points_b = 0;
};

// Both clouds in one frame. Non-finite points are ignored. Never throws; precondition
// cfg.validate() is empty (otherwise returns an invalid result).
NdtResult computeNdtScore(const coral::Points& a, const coral::Points& b, const NdtConfig& cfg);

}  // namespace eval
}  // namespace coral_introspection
