// Input voxel filter for dense clouds (lidar at sensor rate): one centroid per occupied
// voxel, as PCL's VoxelGrid. The CorAl paper voxelises its lidar clouds too (Sec. IV:
// 0.08 m for r = 0.3 m; v = 2 r_min for the warehouse data).
#pragma once

#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace coral {

// Replaces the points of every occupied cube of edge `leaf` [m] (dim 2: square in x, y; z
// is averaged) by their centroid. The output order is a deterministic function of the
// input (hash-table order). Points farther than 2^20 voxels from the origin on an axis are kept
// unfiltered (no integer overflow). leaf <= 0 returns the input. Points must be finite.
Points voxelFilter(const Points& in, double leaf, int dim);

}  // namespace coral
}  // namespace coral_introspection
