// The check_alignment service as a pure function of the request and a config snapshot:
// the same CorAl + classifier path as the stream (online::judgePair), no stream state.
#pragma once

#include "coral_introspection/CheckAlignment.h"
#include "coral_introspection/ros/coral_params.hpp"

namespace coral_introspection {
namespace ros_adapters {

// Empty when the request holds the two scans of a kind this nodelet judges (cloud_a and
// cloud_b for input_type pointcloud, image_a and image_b for polar_image, scan_a and scan_b or
// planar cloud_a and cloud_b for laser_scan); otherwise why it is refused: the other kind (planar
// radar features judged by a 3D lidar nodelet came out "aligned, Q = 0" for any transform), both
// kinds, one scan only, or none. A field counts as given when anything but its header is set.
std::string requestKindError(const CheckAlignment::Request& req, InputType type);

// Fills res->result, and res->error with why there is no verdict (the wrong kind of scans
// for this nodelet, malformed cloud or image, bad transform, too little overlap, ...). Returns
// false when the request itself was malformed (refused), true when it was judged (with or without a
// verdict).
bool answerCheckAlignment(const CheckAlignment::Request& req, const NodeConfig& cfg,
                          CheckAlignment::Response* res);

}  // namespace ros_adapters
}  // namespace coral_introspection
