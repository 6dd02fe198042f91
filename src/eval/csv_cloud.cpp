#include "coral_introspection/eval/csv_cloud.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace coral_introspection {
namespace core {

namespace {
// Numbers separated by commas and/or white space (both layouts occur in libpointmatcher's
// files); the first `skip` fields are ignored. False when a field is not a number.
bool parseNumbers(std::string line, std::size_t skip, std::vector<double>* out) {
  std::replace(line.begin(), line.end(), ',', ' ');
  std::istringstream ss(line);
  std::string field;
  out->clear();
  for (std::size_t col = 0; ss >> field; ++col) {
    if (col < skip) continue;
    std::size_t used = 0;
    try {
      out->push_back(std::stod(field, &used));
    } catch (const std::exception&) {
      return false;
    }
    if (used != field.size()) return false;
  }
  return true;
}
}  // namespace

bool readCsvPoints(const std::string& path, Points* points, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = "cannot open " + path;
    return false;
  }
  points->clear();
  std::string line;
  std::vector<double> v;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    if (!parseNumbers(line, 0, &v) || v.size() < 3) {
      if (n == 1) continue;  // header
      *error = path + ":" + std::to_string(n) + ": expected at least 3 numbers";
      return false;
    }
    points->emplace_back(v[0], v[1], v[2]);
  }
  return true;
}

bool readCsvPose(const std::string& path, const std::string& name, Eigen::Isometry3d* pose,
                 std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = "cannot open " + path;
    return false;
  }
  std::string line;
  std::vector<double> v;
  while (std::getline(in, line)) {
    std::string first = line.substr(0, line.find(','));
    first.erase(first.find_last_not_of(" \t") + 1);
    if (first != name) continue;
    if (!parseNumbers(line, 1, &v) || v.size() != 16) {
      *error = path + ": pose of " + name + " does not have 16 numbers";
      return false;
    }
    Eigen::Matrix4d M;
    for (int i = 0; i < 16; ++i) M(i / 4, i % 4) = v[i];
    pose->matrix() = M;
    return true;
  }
  *error = path + ": no pose for " + name;
  return false;
}

}  // namespace core
}  // namespace coral_introspection
