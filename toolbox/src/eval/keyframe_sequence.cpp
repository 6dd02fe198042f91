#include "coral_introspection/eval/keyframe_sequence.hpp"

#include <sys/stat.h>
#include <algorithm>
#include <cstdio>
#include <fstream>

#include "coral_introspection/coral/validation.hpp"
#include "coral_introspection/eval/cloud_io.hpp"

namespace coral_introspection {
namespace eval {

std::string KeyframeSequenceConfig::validate() const {
  return coral::Problems()
      .require(!scans_dir.empty(), "scans_dir", "non-empty", "\"\"")
      .require(!poses_file.empty(), "poses_file", "non-empty", "\"\"")
      .require(min_range >= 0.0, "min_range", ">= 0 m", min_range)
      .require(max_scans == 0 || max_scans >= 2, "max_scans", "0 or >= 2", max_scans)
      .str();
}

namespace {
bool exists(const std::string& p) {
  struct stat st;
  return stat(p.c_str(), &st) == 0;
}
}  // namespace

bool loadKeyframeSequence(const std::string& folder, const KeyframeSequenceConfig& cfg,
                          const Progress& progress, std::vector<TrainingScan>* scans,
                          coral::Isometries* T_world_scan, std::string* error) {
  if (const std::string e = cfg.validate(); !e.empty()) return coral::fail(error, e);
  if (!readKittiPoses(folder + "/" + cfg.poses_file, T_world_scan, error)) return false;
  std::size_t n = T_world_scan->size();
  if (cfg.max_scans > 0) n = std::min<std::size_t>(n, cfg.max_scans);
  T_world_scan->resize(n);
  std::vector<double> stamps;
  if (std::ifstream t(folder + "/" + cfg.times_file); t)
    for (double s; t >> s;) stamps.push_back(s);
  if (!stamps.empty() && stamps.size() < n)
    return coral::fail(error, folder + "/" + cfg.times_file + ": fewer stamps than poses");
  scans->assign(n, TrainingScan());
  for (std::size_t i = 0; i < n; ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "/%06zu", i);
    std::string path = folder + "/" + cfg.scans_dir + name + ".pcd";
    if (!exists(path)) path = folder + "/" + cfg.scans_dir + name + ".bin";
    LoadedCloud cloud;
    if (!loadCloud(path, &cloud, error, cfg.planar_ok)) return false;
    TrainingScan& s = (*scans)[i];
    s.stamp = stamps.empty() ? static_cast<double>(i) : stamps[i];
    for (const coral::Vec3& p : cloud.points)
      if (p.allFinite() && p.norm() >= cfg.min_range) s.scan.points.push_back(p);
    if (progress) progress(i + 1, n);
  }
  return true;
}

}  // namespace eval
}  // namespace coral_introspection
