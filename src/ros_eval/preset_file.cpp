#include "coral_introspection/ros_eval/preset_file.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace ros_adapters {

namespace {

using XmlRpc::XmlRpcValue;

XmlRpcValue convert(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Map: {
      XmlRpcValue v;
      v.begin();  // makes v an (empty) struct
      for (const auto& kv : n) v[kv.first.as<std::string>()] = convert(kv.second);
      return v;
    }
    case YAML::NodeType::Sequence: {
      XmlRpcValue v;
      v.setSize(static_cast<int>(n.size()));
      for (std::size_t i = 0; i < n.size(); ++i) v[static_cast<int>(i)] = convert(n[i]);
      return v;
    }
    case YAML::NodeType::Scalar: {
      if (n.Tag() == "!") return XmlRpcValue(n.Scalar());  // quoted: a string
      int i = 0;
      double d = 0.0;
      bool b = false;
      if (YAML::convert<int>::decode(n, i)) return XmlRpcValue(i);
      if (YAML::convert<double>::decode(n, d)) return XmlRpcValue(d);
      if (YAML::convert<bool>::decode(n, b)) return XmlRpcValue(b);
      return XmlRpcValue(n.Scalar());
    }
    default:
      return XmlRpcValue();
  }
}

}  // namespace

bool yamlToXmlRpc(const std::string& text, XmlRpcValue* out, std::string* error) {
  try {
    *out = convert(YAML::Load(text));
  } catch (const YAML::Exception& e) {
    return core::fail(error, std::string("YAML: ") + e.what());
  }
  return true;
}

bool loadPresetFile(const std::string& path, NodeConfig* node, core::VerdictConfig* verdict,
                    std::string* error, std::vector<std::string>* warnings) {
  std::ifstream f(path);
  if (!f) return core::fail(error, "cannot open preset " + path);
  std::ostringstream text;
  text << f.rdbuf();
  XmlRpcValue params;
  std::vector<std::string> w;
  if (!yamlToXmlRpc(text.str(), &params, error) || !loadNodeConfig(params, node, error, &w))
    return core::fail(error, path + ": " + *error);
  *verdict = node->online.verdict;  // read by loadNodeConfig, exactly as the nodelet does
  if (warnings) warnings->insert(warnings->end(), w.begin(), w.end());
  return true;
}

}  // namespace ros_adapters
}  // namespace coral_introspection
