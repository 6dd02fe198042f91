#include "coral_introspection/eval/oxford_dataset.hpp"

#include "coral_introspection/coral/validation.hpp"

#include <sys/stat.h>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <utility>

#include "coral_introspection/config/text_fields.hpp"
#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace eval {

namespace {
bool isFile(const std::string& p) {
  struct stat st;
  return stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}
using Key = std::pair<int64_t, int64_t>;  // (source, destination) radar stamps [us]
}  // namespace

bool OxfordDataset::load(const std::string& dir, std::string* error) {
  folder = dir;
  stamps_us.clear();
  png_paths.clear();
  T_prev_curr.clear();
  std::ifstream ts(dir + "/radar.timestamps");
  if (!ts) return coral::fail(error, "cannot open " + dir + "/radar.timestamps");
  int64_t stamp = 0;
  int valid = 0;
  std::string line;
  while (std::getline(ts, line)) {
    std::istringstream ls(line);
    if (!(ls >> stamp)) continue;
    if (!(ls >> valid)) valid = 1;
    const std::string png = dir + "/radar/" + std::to_string(stamp) + ".png";
    if (valid != 1 || !isFile(png)) continue;
    stamps_us.push_back(stamp);
    png_paths.push_back(png);
  }
  if (stamps_us.empty()) return coral::fail(error, "no valid radar scan listed in " + dir);

  // gt/radar_odometry.csv: x, y, yaw (cols 2, 3, 7) of the pose of the source scan in the
  // destination scan's frame, keyed by the radar stamps (cols 8, 9).
  const std::string gt_path = dir + "/gt/radar_odometry.csv";
  std::ifstream gt(gt_path);
  if (!gt) return coral::fail(error, "cannot open " + gt_path);
  std::map<Key, Eigen::Isometry3d> rel;
  std::getline(gt, line);  // header
  while (std::getline(gt, line)) {
    const std::vector<std::string> f = config::splitFields(line, ',');
    if (f.size() < 10) continue;
    // Whole finite numbers only: std::stod read "0.5x" as 0.5 and "nan" as a pose.
    double x, y, yaw;
    long source, destination;
    const long max_stamp = std::numeric_limits<long>::max();
    if (!config::parseFiniteNumber(f[2], &x) || !config::parseFiniteNumber(f[3], &y) ||
        !config::parseFiniteNumber(f[7], &yaw) ||
        !config::parseInteger(f[8], 0, max_stamp, &source) ||
        !config::parseInteger(f[9], 0, max_stamp, &destination))
      return coral::fail(error, gt_path + ": malformed row '" + line + "'");
    rel[{source, destination}] = coral::se2(x, y, yaw);
  }
  T_prev_curr.push_back(Eigen::Isometry3d::Identity());
  for (std::size_t i = 1; i < stamps_us.size(); ++i) {
    auto it = rel.find({stamps_us[i], stamps_us[i - 1]});
    if (it != rel.end()) {
      T_prev_curr.push_back(it->second);
      continue;
    }
    it = rel.find({stamps_us[i - 1], stamps_us[i]});  // reverse row: invert it
    if (it == rel.end())
      return coral::fail(error, gt_path + ": no GT row between scans " +
                                    std::to_string(stamps_us[i - 1]) + " and " +
                                    std::to_string(stamps_us[i]));
    T_prev_curr.push_back(it->second.inverse());
  }
  return true;
}

Eigen::Isometry3d OxfordDataset::T_first_scan(std::size_t i) const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (std::size_t j = 1; j <= i && j < T_prev_curr.size(); ++j) T = T * T_prev_curr[j];
  return T;
}

}  // namespace eval
}  // namespace coral_introspection
