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

const XmlRpcValue* find(const XmlRpcValue& root, const std::string& group, const std::string& key) {
  if (root.getType() != XmlRpcValue::TypeStruct || !root.hasMember(group)) return nullptr;
  const XmlRpcValue& g = root[group];
  if (g.getType() != XmlRpcValue::TypeStruct || !g.hasMember(key)) return nullptr;
  return &g[key];
}

bool getNumber(const XmlRpcValue& root, const char* group, const char* key, double* out,
               std::string* error) {
  const XmlRpcValue* v = find(root, group, key);
  if (v == nullptr) return true;
  if (v->getType() == XmlRpcValue::TypeDouble)
    *out = static_cast<double>(*v);
  else if (v->getType() == XmlRpcValue::TypeInt)
    *out = static_cast<int>(*v);
  else
    return core::fail(error, std::string("parameter ~") + group + "/" + key + " must be a number");
  return true;
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

bool loadVerdictConfig(const XmlRpcValue& params, core::VerdictConfig* v, std::string* error) {
  if (const XmlRpcValue* m = find(params, "classifier", "method")) {
    if (m->getType() != XmlRpcValue::TypeString ||
        !core::parseVerdictMethod(static_cast<std::string>(*m), &v->method))
      return core::fail(error, "parameter ~classifier/method must be classifier, relative or both");
  }
  return getNumber(params, "tolerance", "translation", &v->tolerance.translation, error) &&
         getNumber(params, "tolerance", "rotation_deg", &v->tolerance.rotation_deg, error) &&
         getNumber(params, "classifier", "relative_margin", &v->relative.margin, error) &&
         getNumber(params, "classifier", "flat_ratio", &v->relative.flat_ratio, error);
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
  // Default tolerance of the preset's sensor class, then the file's values.
  verdict->tolerance = core::ToleranceConfig::forSensor(node->input_type == InputType::kPolarImage,
                                                        node->coral.dimension);
  verdict->classifier = node->classifier;
  if (!loadVerdictConfig(params, verdict, error)) return core::fail(error, path + ": " + *error);
  if (const std::string e = verdict->validate(); !e.empty())
    return core::fail(error, path + ": " + e);
  if (warnings)  // the verdict keys are known here even though loadNodeConfig skips them
    for (const std::string& s : w)
      if (s.find("~classifier/method") == std::string::npos &&
          s.find("~classifier/relative_margin") == std::string::npos &&
          s.find("~classifier/flat_ratio") == std::string::npos)
        warnings->push_back(s);
  if (warnings && params.getType() == XmlRpcValue::TypeStruct && params.hasMember("tolerance") &&
      params["tolerance"].getType() == XmlRpcValue::TypeStruct)
    for (const auto& kv : params["tolerance"])
      if (kv.first != "translation" && kv.first != "rotation_deg")
        warnings->push_back("unknown parameter ~tolerance/" + kv.first + " (ignored)");
  return true;
}

}  // namespace ros_adapters
}  // namespace coral_introspection
