// Parameters of CoralNodelet: one struct holding every setting (defaults = the core
// config defaults), loaded from the private namespace and validated before anything
// starts. Loading works on an XmlRpc tree so it is unit-tested without a ROS master.
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

#include <string>
#include <vector>

#include "coral_introspection/coral/classifier.hpp"
#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/online/pairing.hpp"
#include "coral_introspection/radar/doppler.hpp"
#include "coral_introspection/radar/polar_scan.hpp"
#include "coral_introspection/radar/rip_features.hpp"

namespace coral_introspection {
namespace ros_adapters {

enum class InputType { kPointCloud, kPolarImage };
enum class PolarFormat { kOxford, kPlain };

struct DopplerParams {
  bool enabled = false;
  std::string velocity_field = "velocity";  // PointCloud2 field with the radial velocity [m/s]
  core::DopplerConfig check;                // doppler/* thresholds (core/doppler.hpp)
};

struct NodeConfig {
  InputType input_type = InputType::kPointCloud;
  std::string fixed_frame = "odom";
  int queue_size = 10;      // scans waiting for TF in the message filter
  double tf_timeout = 1.0;  // [s] wall time a scan may wait for TF before it counts as failed
  online::PairingConfig pairing;
  core::CoralConfig coral;
  core::ClassifierConfig classifier;
  PolarFormat polar_format = PolarFormat::kOxford;
  core::PolarImageConfig polar;  // used by polar_format plain (oxford: fixed layout)
  core::RipConfig rip;
  bool motion_compensation = true;  // radar: de-skew features with the TF velocity
  bool publish_quality_cloud = true;
  bool publish_features = true;
  DopplerParams doppler;

  std::string validate() const;  // empty when valid; names the parameter, value and range
};

// Reads the private parameter tree `params` (a struct, e.g. from
// nh.getParam(pnh.getNamespace(), v); an invalid/empty value means "no parameters set").
// Missing keys keep their defaults. Returns false with *error naming the parameter, the
// value and the allowed range / type on the first problem, then on validate(). Unknown keys
// inside the known groups (coral/, rip/, ...) are reported in *warnings (likely typos).
bool loadNodeConfig(const XmlRpc::XmlRpcValue& params, NodeConfig* cfg, std::string* error,
                    std::vector<std::string>* warnings = nullptr);

}  // namespace ros_adapters
}  // namespace coral_introspection
