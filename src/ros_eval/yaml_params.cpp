#include "coral_introspection/ros_eval/yaml_params.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace coral_introspection {
namespace ros_adapters {

namespace {

using XmlRpc::XmlRpcValue;

std::string where(const YAML::Node& n) {
  const YAML::Mark m = n.Mark();
  return " at line " + std::to_string(m.line + 1) + ", column " + std::to_string(m.column + 1);
}

// A plain scalar typed like rosparam's YAML 1.1 loader: bool, int, float, else string.
XmlRpcValue scalar(const YAML::Node& n) {
  const std::string s = n.Scalar();
  if (n.Tag() == "!") return XmlRpcValue(s);  // quoted: always a string
  std::string low = s;
  std::transform(low.begin(), low.end(), low.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (low == "true" || low == "yes" || low == "on") return XmlRpcValue(true);
  if (low == "false" || low == "no" || low == "off") return XmlRpcValue(false);
  if (!s.empty()) {
    char* end = nullptr;
    const long i = std::strtol(s.c_str(), &end, 10);
    if (*end == '\0' && i >= INT32_MIN && i <= INT32_MAX) return XmlRpcValue(static_cast<int>(i));
    const double d = std::strtod(s.c_str(), &end);
    const bool numeric = std::any_of(s.begin(), s.end(), [](char c) { return std::isdigit(c); });
    if (*end == '\0' && numeric) return XmlRpcValue(d);
  }
  return XmlRpcValue(s);
}

bool convert(const YAML::Node& n, XmlRpcValue* out, std::string* error) {
  switch (n.Type()) {
    case YAML::NodeType::Scalar:
      *out = scalar(n);
      return true;
    case YAML::NodeType::Sequence: {
      out->setSize(static_cast<int>(n.size()));
      for (std::size_t i = 0; i < n.size(); ++i)
        if (!convert(n[i], &(*out)[static_cast<int>(i)], error)) return false;
      return true;
    }
    case YAML::NodeType::Map: {
      *out = XmlRpcValue();
      out->begin();  // makes it an (empty) struct
      for (const auto& kv : n) {
        XmlRpcValue v;
        if (!convert(kv.second, &v, error)) return false;
        (*out)[kv.first.as<std::string>()] = v;
      }
      return true;
    }
    default:
      *error = "empty (null) value" + where(n) + " (give a value or remove the key)";
      return false;
  }
}

}  // namespace

bool parseYamlParams(const std::string& text, XmlRpcValue* tree, std::string* error) {
  try {
    const YAML::Node root = YAML::Load(text);
    if (!root.IsMap()) {
      *error = "the top level must be a map of parameters";
      return false;
    }
    return convert(root, tree, error);
  } catch (const YAML::Exception& e) {
    *error = std::string("YAML: ") + e.what();
    return false;
  }
}

bool loadYamlParams(const std::string& path, XmlRpcValue* tree, std::string* error) {
  std::ifstream f(path);
  if (!f) {
    *error = "cannot read parameter file " + path;
    return false;
  }
  std::stringstream ss;
  ss << f.rdbuf();
  if (!parseYamlParams(ss.str(), tree, error)) {
    *error = path + ": " + *error;
    return false;
  }
  return true;
}

void mergeParams(const XmlRpcValue& overlay, XmlRpcValue* base) {
  if (overlay.getType() != XmlRpcValue::TypeStruct) return;
  if (base->getType() != XmlRpcValue::TypeStruct) *base = XmlRpcValue();
  for (auto it = overlay.begin(); it != overlay.end(); ++it) {
    if (it->second.getType() == XmlRpcValue::TypeStruct && base->hasMember(it->first) &&
        (*base)[it->first].getType() == XmlRpcValue::TypeStruct)
      mergeParams(it->second, &(*base)[it->first]);
    else
      (*base)[it->first] = it->second;
  }
}

}  // namespace ros_adapters
}  // namespace coral_introspection
