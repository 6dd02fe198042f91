// Reading point clouds and poses stored as CSV text (libpointmatcher's format: a header
// line, then x, y, z[, more columns] per line). ROS-free.
#pragma once

#include <string>

#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace core {

// Reads the first three numeric columns of every data line. The first line is skipped
// when it is not numeric (a header). False with a message on a missing file or bad line.
bool readCsvPoints(const std::string& path, Points* points, std::string* error);

// Reads a 4x4 row-major pose (16 numbers after the first column) for the row whose
// first column equals `name` (libpointmatcher's carCloudList.csv).
bool readCsvPose(const std::string& path, const std::string& name, Eigen::Isometry3d* pose,
                 std::string* error);

}  // namespace core
}  // namespace coral_introspection
