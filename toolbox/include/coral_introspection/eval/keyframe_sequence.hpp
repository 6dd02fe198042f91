// A lidar keyframe sequence: <folder>/Scans/<index, 6 digits>.pcd (or .bin) in the
// sensor/body frame, a KITTI-layout pose file (one 3x4 world_T_body per keyframe, line i =
// keyframe i) and optionally times.txt (one stamp [s] per keyframe), as written by
// FAST-LIO / scan-context pose graphs (../shared/data/hku1_livox_keyframes).
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/eval/training_set.hpp"

namespace coral_introspection {
namespace eval {

struct KeyframeSequenceConfig {
  std::string scans_dir = "Scans";                 // relative to the folder
  std::string poses_file = "optimized_poses.txt";  // KITTI layout, world_T_body
  std::string times_file = "times.txt";            // optional; absent: stamp = index
  double min_range = 0.0;                          // [m] closer points dropped (0 = keep)
  int max_scans = 0;                               // first N keyframes; 0 = all
  // PCDs with fields x and y only are planar scans (z = 0), as loadCloud's planar_ok: for a
  // reader that judges them in 2D (coral_pose_graph under a 2D preset); else refused.
  bool planar_ok = false;
  std::string validate() const;  // empty when valid
};

// Scans in their own sensor frames (origin 0) and poses T_world_scan, one per keyframe.
// False with *error on a missing/unreadable scan or pose file or a count mismatch.
bool loadKeyframeSequence(const std::string& folder, const KeyframeSequenceConfig& cfg,
                          const Progress& progress, std::vector<TrainingScan>* scans,
                          coral::Isometries* T_world_scan, std::string* error);

}  // namespace eval
}  // namespace coral_introspection
