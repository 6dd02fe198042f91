// Scan-pair data sets with accurate relative poses, ROS-free, named on the command line as
// "[name=]kind:path":
//   oxford:DIR          Oxford Radar RobotCar folder, consecutive scans (RIP features)
//   keyframes:DIR       lidar keyframes + KITTI poses (keyframe_sequence.hpp), consecutive
//   carmen:FILE         CARMEN .clf[.bz2] + FILE's .relations (carmen_log.hpp), one pair
//                       per ground-truth relation
//   cloudlist:FILE      a list "name, 4x4 row-major pose" (libpointmatcher's *List.csv) of
//                       clouds beside it; consecutive entries form pairs
// (rosbags are read by ros_eval, which adds the kind "bag:FILE").
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/eval/carmen_log.hpp"
#include "coral_introspection/eval/keyframe_sequence.hpp"
#include "coral_introspection/eval/oxford_training.hpp"

namespace coral_introspection {
namespace eval {

struct DatasetSpec {
  std::string name;  // report label; default: the path's last component without extension
  std::string kind;  // oxford | keyframes | carmen | cloudlist | bag
  std::string path;
};

// Parses "[name=]kind:path". False with *error on an unknown kind or an empty path.
bool parseDatasetSpec(const std::string& text, DatasetSpec* spec, std::string* error);

struct DatasetOptions {
  OxfordTrainingConfig oxford;       // RIP settings of the radar preset
  KeyframeSequenceConfig keyframes;  // file names, range gate
  LaserGeometry laser;               // CARMEN beam geometry
  double spacing = 0.0;              // [m] sequences: min distance between paired scans
};

struct PairDataset {
  std::string name;
  std::vector<TrainingScan> scans;  // sensor frames, origin 0
  std::vector<ScanPair> pairs;
  std::string summary;  // e.g. "314 scans, 313 consecutive pairs"
};

// Loads a ROS-free kind. False with *error on unreadable files; never throws.
bool loadPairDataset(const DatasetSpec& spec, const DatasetOptions& options,
                     const Progress& progress, PairDataset* out, std::string* error);

}  // namespace eval
}  // namespace coral_introspection
