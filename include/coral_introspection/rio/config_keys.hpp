// Key checking of the rio YAML files (the estimator's groups and the adapters' `ros` group):
// a key no setting reads is an error naming the nearest valid key, never a silent default.
// A misspelt group ("extrinsic:") would otherwise leave its settings at their defaults
// (identity extrinsics) with nothing but a warning.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

namespace coral_introspection {
namespace rio {

// " (did you mean X?)" for the entry of `valid` nearest to `name`, "" when none is close
// (edit distance of the last path component at most max(2, length / 3); a candidate in
// another group costs one more, so a key put into the wrong group finds its group).
// Names are "key" or "group/key".
std::string didYouMean(const std::string& name, const std::vector<std::string>& valid);

// Problems with the keys of `root` ("; "-joined, empty when none): a top-level key that is
// neither a group of `valid` ("group/key" entries), nor a top-level entry of `valid`, nor in
// `other_groups`; a key of a group that `valid` does not list; a group that is not a map.
// Messages name keys as `prefix` + key (e.g. "ros/").
std::string unknownKeys(const YAML::Node& root, const std::vector<std::string>& valid,
                        const std::vector<std::string>& other_groups,
                        const std::string& prefix = "");

}  // namespace rio
}  // namespace coral_introspection
