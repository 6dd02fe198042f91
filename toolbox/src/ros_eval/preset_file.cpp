#include "coral_introspection/ros_eval/preset_file.hpp"

#include "coral_introspection/config/yaml_tree.hpp"

namespace coral_introspection {
namespace ros_eval {

bool loadPresetFiles(const std::vector<std::string>& paths, ros_adapters::NodeConfig* node,
                     std::string* error) {
  config::ParamTree tree;
  for (const std::string& path : paths) {
    config::ParamTree file;
    if (!config::loadYamlFile(path, &file, error)) return false;
    tree.merge(file);
  }
  return ros_adapters::loadNodeConfig(tree, node, error);
}

bool loadPresetFile(const std::string& path, ros_adapters::NodeConfig* node,
                    coral::VerdictConfig* verdict, std::string* error) {
  if (!loadPresetFiles({path}, node, error)) return false;
  *verdict = node->online.verdict;  // read by loadNodeConfig, exactly as the nodelet does
  return true;
}

}  // namespace ros_eval
}  // namespace coral_introspection
