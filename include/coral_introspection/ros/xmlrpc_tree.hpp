// The parameter server's view of a namespace (an XmlRpc struct, from
// nh.getParam(pnh.getNamespace(), v)) as a config::ParamTree: structs become groups, arrays
// of scalars lists, int/double/bool/string scalars. The only place where XmlRpc meets the
// configuration layer; the loaders read the tree (config/param_tree.hpp).
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

#include <string>

#include "coral_introspection/config/param_tree.hpp"

namespace coral_introspection {
namespace ros_adapters {

// An invalid (unset) value gives an empty tree. False with *error naming the parameter on a
// value the tree cannot hold (a date, binary data, a struct inside an array).
bool fromXmlRpc(const XmlRpc::XmlRpcValue& value, config::ParamTree* out, std::string* error);

}  // namespace ros_adapters
}  // namespace coral_introspection
