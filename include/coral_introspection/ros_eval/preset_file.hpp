// A sensor preset file (config/*.yaml) read exactly as the nodelet reads its private
// parameters: the YAML (yaml-cpp) becomes an XmlRpc tree that loadNodeConfig() checks, so
// training uses the preset's CorAl / RIP settings and re-training after a preset change
// needs no code change. The verdict settings (tolerance/*, classifier/method,
// classifier/relative_margin, classifier/flat_ratio) are the nodelet's too
// (NodeConfig::online.verdict): *verdict is a copy of them.
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

#include <string>
#include <vector>

#include "coral_introspection/coral/verdict.hpp"
#include "coral_introspection/ros/params.hpp"

namespace coral_introspection {
namespace ros_adapters {

// YAML text -> XmlRpc tree (maps -> structs, sequences -> arrays; plain scalars become
// int, double, bool or string in that order of preference, quoted scalars stay strings).
bool yamlToXmlRpc(const std::string& yaml_text, XmlRpc::XmlRpcValue* out, std::string* error);

// Reads and validates a preset file. Warnings: unknown keys (likely typos).
bool loadPresetFile(const std::string& path, NodeConfig* node, core::VerdictConfig* verdict,
                    std::string* error, std::vector<std::string>* warnings = nullptr);

}  // namespace ros_adapters
}  // namespace coral_introspection
