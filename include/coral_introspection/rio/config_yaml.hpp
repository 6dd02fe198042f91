// RioConfig from a parameter tree (config/param_tree.hpp, read from a YAML file): the one
// loader used by rio_offline, the ROS-free tools and RioNodelet (its config_file). Keys mirror
// the config structs: imu/..., extrinsics/translation [x, y, z], extrinsics/rotation
// [qx, qy, qz, qw], radar_time_offset, time_offset/..., uncertainty/..., front_end/...,
// association/..., solver/..., init/..., zero_velocity/..., health/..., barometer/.... Missing
// settings keep their defaults, except the extrinsics (no default is right for a sensor rig:
// identity would be a guess). A group or key no setting reads is an error naming the nearest
// valid name, as are duplicate keys (config/yaml_tree.hpp). Never throws.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "coral_introspection/config/param_tree.hpp"
#include "coral_introspection/rio/config.hpp"

namespace coral_introspection {
namespace rio {

// What a caller expects of the file besides the estimator's settings.
struct RioConfigRules {
  // Top-level groups read by someone else (the adapters' "ros"): not unknown.
  std::vector<std::string> other_groups;
  // extrinsics/translation and extrinsics/rotation must be given. False only where the
  // extrinsics come from elsewhere (RioNodelet with extrinsics_source tf).
  bool require_extrinsics = true;
};

// Reads the groups above from `tree` into *cfg, then validates. On error returns false with
// *error naming the key (and, from a file, "file:line"): an empty file, a wrong type, an
// unknown key or group (with the nearest valid name), a missing required setting, an
// invalid value. `tree` records what was read (the caller may read other groups from it).
bool loadRioConfig(config::ParamTree& tree, RioConfig* cfg, std::string* error,
                   const RioConfigRules& rules = {});
// The same from a YAML document (no file locations in messages).
bool loadRioConfig(const YAML::Node& root, RioConfig* cfg, std::string* error,
                   const RioConfigRules& rules = {});

// The same from a file.
bool loadRioConfigFile(const std::string& path, RioConfig* cfg, std::string* error,
                       const RioConfigRules& rules = {});

// Applies one "group/key=value" assignment (value parsed as YAML) to tree, e.g.
// "solver/window_size=8" or "extrinsics/translation=[0, 0, 0.1]". False with *error when
// the assignment is malformed.
bool applyOverride(config::ParamTree& tree, const std::string& assignment, std::string* error);

const char* toString(UncertaintyMode m);

}  // namespace rio
}  // namespace coral_introspection
