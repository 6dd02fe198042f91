// YAML (yaml-cpp) -> config::ParamTree, typed as rosparam types a file it loads into the
// parameter server, so that a preset means the same to coral_check as to the nodelet: a
// quoted scalar is a string; a plain scalar is a bool (true/false/yes/no/on/off, any case),
// else an integer, else a number (also .inf/.nan), else a string. Maps become groups,
// sequences of scalars lists.
//
// Duplicate keys are errors: yaml-cpp keeps both and its lookups see only one, so a group
// given twice (`coral:` at line 3 and at line 20) would silently lose one of them.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

#include "coral_introspection/config/param_tree.hpp"

namespace coral_introspection {
namespace config {

// The tree of a parsed document; `source` (a file name) makes every node's location
// "source:line" (empty: no locations). An empty document gives an empty tree. False with
// *error on a top level that is not a map, a duplicate key ("duplicate key coral (lines 3
// and 20)"), a nested sequence or a map inside a sequence.
bool fromYaml(const YAML::Node& document, ParamTree* out, std::string* error,
              const std::string& source = "");
// YAML text (source as above) and files (source = path); syntax errors name the line.
bool parseYaml(const std::string& text, ParamTree* out, std::string* error,
               const std::string& source = "");
bool loadYamlFile(const std::string& path, ParamTree* out, std::string* error);

}  // namespace config
}  // namespace coral_introspection
