// The check_alignment service as a pure function of the request and a config snapshot:
// the same CorAl + classifier path as the stream (online::judgePair), no stream state.
#pragma once

#include "coral_introspection/CheckAlignment.h"
#include "coral_introspection/ros/params.hpp"

namespace coral_introspection {
namespace ros_adapters {

// Fills res->result, and res->error with why there is no verdict (malformed cloud or
// image, bad transform, too little overlap, ...). Returns false when the request itself
// was malformed (refused), true when it was judged (with or without a verdict).
bool answerCheckAlignment(const CheckAlignment::Request& req, const NodeConfig& cfg,
                          CheckAlignment::Response* res);

}  // namespace ros_adapters
}  // namespace coral_introspection
