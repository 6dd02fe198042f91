#include "coral_introspection/ros/xmlrpc_tree.hpp"

namespace coral_introspection {
namespace ros_adapters {

namespace {

using XmlRpc::XmlRpcValue;

bool scalar(XmlRpcValue& v, config::Scalar* out) {
  switch (v.getType()) {
    case XmlRpcValue::TypeBoolean:
      *out = config::Scalar::ofBool(static_cast<bool>(v));
      return true;
    case XmlRpcValue::TypeInt:
      *out = config::Scalar::ofInt(static_cast<int>(v));
      return true;
    case XmlRpcValue::TypeDouble:
      *out = config::Scalar::ofDouble(static_cast<double>(v));
      return true;
    case XmlRpcValue::TypeString:
      *out = config::Scalar::ofString(static_cast<std::string>(v));
      return true;
    default:
      return false;
  }
}

// XmlRpcValue's accessors are non-const: the conversion works on a copy.
bool convert(XmlRpcValue& v, const std::string& path, config::ParamNode* out, std::string* error) {
  using Kind = config::ParamNode::Kind;
  if (v.getType() == XmlRpcValue::TypeStruct) {
    out->kind = Kind::kGroup;
    for (auto it = v.begin(); it != v.end(); ++it) {
      config::ParamNode child;
      const std::string child_path = path.empty() ? it->first : path + "/" + it->first;
      if (!convert(it->second, child_path, &child, error)) return false;
      out->children.emplace_back(it->first, std::move(child));
    }
    return true;
  }
  if (v.getType() == XmlRpcValue::TypeArray) {
    out->kind = Kind::kList;
    out->list.resize(static_cast<std::size_t>(v.size()));
    for (int i = 0; i < v.size(); ++i)
      if (!scalar(v[i], &out->list[static_cast<std::size_t>(i)])) {
        *error = "parameter " + path + ": a list may hold only values (numbers, strings, bools)";
        return false;
      }
    return true;
  }
  // No value (an empty XmlRpcValue inside a struct): as a YAML key without a value, an empty
  // group where a group is read and an error where a value is read.
  if (v.getType() == XmlRpcValue::TypeInvalid) {
    out->kind = Kind::kNull;
    return true;
  }
  out->kind = Kind::kScalar;
  if (scalar(v, &out->scalar)) return true;
  *error = "parameter " + path + " has a type the parameters cannot hold (date or binary)";
  return false;
}

}  // namespace

bool fromXmlRpc(const XmlRpc::XmlRpcValue& value, config::ParamTree* out, std::string* error) {
  if (value.getType() == XmlRpcValue::TypeInvalid) {
    *out = config::ParamTree();
    return true;
  }
  XmlRpcValue copy = value;
  if (copy.getType() != XmlRpcValue::TypeStruct) {
    *error = "the parameters must be a map of groups and parameters";
    return false;
  }
  config::ParamNode root;
  if (!convert(copy, "", &root, error)) return false;
  *out = config::ParamTree(std::move(root));
  return true;
}

}  // namespace ros_adapters
}  // namespace coral_introspection
