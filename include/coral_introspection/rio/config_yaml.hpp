// RioConfig from a YAML tree (yaml-cpp): the one loader used by rio_offline (a YAML file),
// the ROS-free tools and the nodelet (its parameter tree converted to YAML). Keys mirror
// the config structs: imu/..., extrinsics/translation [x, y, z], extrinsics/rotation
// [qx, qy, qz, qw], radar_time_offset, uncertainty/..., front_end/..., association/...,
// solver/..., init/..., zero_velocity/..., health/.... Missing keys keep their defaults.
// Never throws.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "coral_introspection/rio/config.hpp"

namespace coral_introspection {
namespace rio {

// Reads the groups above from root into *cfg, then validates. On error returns false with
// *error naming the key. Keys inside the known groups that no setting reads are reported
// in *warnings (likely typos); top-level keys not listed in `other_groups` too.
bool loadRioConfig(const YAML::Node& root, RioConfig* cfg, std::string* error,
                   std::vector<std::string>* warnings = nullptr,
                   const std::vector<std::string>& other_groups = {});

// The same from a file.
bool loadRioConfigFile(const std::string& path, RioConfig* cfg, std::string* error,
                       std::vector<std::string>* warnings = nullptr,
                       const std::vector<std::string>& other_groups = {});

// Applies one "group/key=value" assignment (value parsed as YAML) to root, e.g.
// "solver/window_size=8" or "extrinsics/translation=[0, 0, 0.1]". False with *error when
// the assignment is malformed.
bool applyOverride(YAML::Node& root, const std::string& assignment, std::string* error);

const char* toString(UncertaintyMode m);

}  // namespace rio
}  // namespace coral_introspection
