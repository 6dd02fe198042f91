// Point clouds, transforms and pose lists from files, for tools and tests. ROS-free.
//  - .pcd (ascii / binary / binary_compressed): read with PCL's PCD reader; fields x y z
//    of TYPE F (SIZE 4 or 8), [intensity] of any PCD type, each read exactly; integer
//    coordinates, undefined TYPE / SIZE pairs and COUNT other than 1 are refused, and so is a
//    VIEWPOINT other than 0 0 0 1 0 0 0 (the points must be in their sensor's frame);
//  - .bin (KITTI / Velodyne): float32 records x, y, z, intensity;
//  - .csv (libpointmatcher): a header line, then x, y, z[, more columns] per line.
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace eval {

struct LoadedCloud {
  coral::Points points;           // as stored (non-finite points kept: CorAl drops them)
  std::vector<double> intensity;  // same size as points, or empty when the file has none
  // A PCD with fields x and y but no z (a planar scan written without its zeros), read with
  // z = 0: only when the caller allows planar PCDs (loadCloud).
  bool planar = false;
};

// Chooses the reader by the file extension (.pcd, .bin, .csv; case-insensitive). False
// with a message naming the file on a missing/unreadable file, a malformed record or an
// unknown extension. Never throws. A PCD without z is refused unless planar_ok (a reader
// that can tell a 2D scan from a flat 3D cloud: coral_check, by its preset's dimension).
bool loadCloud(const std::string& path, LoadedCloud* cloud, std::string* error,
               bool planar_ok = false);

// Reads the first three numeric columns of every data line. The first line is skipped
// when it is not numeric (a header). False with a message on a missing file or bad line.
bool readCsvPoints(const std::string& path, coral::Points* points, std::string* error);

// Reads a 4x4 row-major pose (16 numbers after the first column) for the row whose
// first column equals `name` (libpointmatcher's carCloudList.csv).
bool readCsvPose(const std::string& path, const std::string& name, Eigen::Isometry3d* pose,
                 std::string* error);

// A 4x4 or 3x4 row-major matrix (12 or 16 numbers separated by white space and/or commas;
// a 4x4 must end in 0 0 0 1). The rotation must be orthonormal to 1e-4 (then it is
// re-orthonormalised), so a typo does not silently become a shear.
bool readTransformFile(const std::string& path, Eigen::Isometry3d* T, std::string* error);

// A KITTI-layout pose list: one 3x4 row-major world_T_body per line (12 numbers).
bool readKittiPoses(const std::string& path, coral::Isometries* poses, std::string* error);

}  // namespace eval
}  // namespace coral_introspection
