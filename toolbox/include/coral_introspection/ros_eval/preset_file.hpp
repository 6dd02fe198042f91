// Sensor preset files (config/*.yaml) read exactly as the nodelet reads its private
// parameters: straight into a config::ParamTree that ros_adapters::loadNodeConfig() checks,
// so training uses the preset's CorAl / RIP settings and re-training after a preset change
// needs no code change. The verdict settings (tolerance/*, classifier/method,
// classifier/relative_margin, classifier/flat_ratio) are the nodelet's too
// (NodeConfig::online.verdict): *verdict is a copy of them.
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/coral/verdict.hpp"
#include "coral_introspection/ros/coral_params.hpp"

namespace coral_introspection {
namespace ros_eval {

// Reads and validates preset files, each later one loaded over the earlier ones key by key
// (a classifier file from coral_train over its preset), as roslaunch's <rosparam
// command="load"> puts them into one namespace. Errors name the file (and the line):
// "p.yaml:3: unknown group coarl (did you mean coral?)", "p.yaml: duplicate key coral
// (lines 3 and 20)", a wrong type, a value out of range.
bool loadPresetFiles(const std::vector<std::string>& paths, ros_adapters::NodeConfig* node,
                     std::string* error);

// One preset file.
bool loadPresetFile(const std::string& path, ros_adapters::NodeConfig* node,
                    coral::VerdictConfig* verdict, std::string* error);

}  // namespace ros_eval
}  // namespace coral_introspection
