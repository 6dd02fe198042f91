// Parameter files (the config/*.yaml presets, classifier files) read into the same XmlRpc
// tree rosparam would load, so offline tools (coral_check) hand them to the nodelet's own
// loader (ros_adapters::loadNodeConfig) without a ROS master: a preset means exactly the
// same thing in both.
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

#include <string>

namespace coral_introspection {
namespace ros_adapters {

// Parses YAML text as rosparam does: plain scalars become bool (true/false/yes/no/on/off),
// int, double or string; quoted scalars stay strings; maps become structs, sequences
// arrays. False with a message (line and column) on a syntax error, a null value or a
// top level that is not a map.
bool parseYamlParams(const std::string& text, XmlRpc::XmlRpcValue* tree, std::string* error);
bool loadYamlParams(const std::string& path, XmlRpc::XmlRpcValue* tree, std::string* error);

// Copies every key of `overlay` into `base`, recursing into structs present in both
// (a classifier file loaded over a preset replaces its classifier/ values).
void mergeParams(const XmlRpc::XmlRpcValue& overlay, XmlRpc::XmlRpcValue* base);

}  // namespace ros_adapters
}  // namespace coral_introspection
