// Parameters of CoralNodelet: one struct holding every setting (defaults = the core and
// online config defaults), loaded from the private namespace and validated before anything
// starts. Loading works on an XmlRpc tree so it is unit-tested without a ROS master.
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

#include <string>
#include <vector>

#include "coral_introspection/online/introspector_config.hpp"
#include "coral_introspection/radar/polar_scan.hpp"
#include "coral_introspection/radar/rip_features.hpp"

namespace coral_introspection {
namespace ros_adapters {

enum class InputType { kPointCloud, kPolarImage };
enum class PolarFormat { kOxford, kPlain };

struct NodeConfig {
  InputType input_type = InputType::kPointCloud;
  std::string fixed_frame = "odom";
  int queue_size = 10;      // scans waiting for TF in the message filter
  double tf_timeout = 1.0;  // [s] wall time a scan may wait for TF before it counts as failed
  // [s] worker time per scan (de-skew, CorAl, classifier) above which diagnostics warn, also
  // while the scan is still being computed; 0 = off. About the scan period: beyond it, scans
  // are dropped.
  double time_budget = 1.0;
  // [s] testing only: the worker sleeps this long after each judged pair (a deliberately
  // slow pair for the responsiveness tests). 0 in any real use.
  double testing_pair_delay = 0.0;
  // [s] after a scan, the worker returns the allocator's free pages to the system
  // (ros_adapters::releaseFreeHeap) at most once per this interval; 0 = never. Keeps image
  // buffers freed after a pile-up from staying resident (doc/testing.md, soak run 3).
  double heap_release_interval = 10.0;
  // pairing/, coral/, classifier/, motion_compensation/, doppler/: the Introspector's config.
  // Polar input requires coral/dimension 2 (RIP features are planar: 3D covariances of
  // z = 0 points are singular), checked by validate() rather than switched silently.
  online::IntrospectorConfig online;
  PolarFormat polar_format = PolarFormat::kOxford;
  core::PolarImageConfig polar;  // used by polar_format plain (oxford: fixed layout)
  core::RipConfig rip;
  bool publish_quality_cloud = true;
  bool publish_features = true;
  std::string velocity_field = "velocity";  // doppler/velocity_field: radial velocity [m/s]

  std::string validate() const;  // empty when valid; names the parameter, value and range
};
// Reads the private parameter tree `params` (a struct, e.g. from
// nh.getParam(pnh.getNamespace(), v); an invalid/empty value means "no parameters set").
// Missing keys keep their defaults. Returns false with *error naming the parameter, the
// value and the allowed range / type on the first problem, then on validate(). Unknown keys
// inside the known groups (coral/, rip/, ...) are reported in *warnings (likely typos).
bool loadNodeConfig(const XmlRpc::XmlRpcValue& params, NodeConfig* cfg, std::string* error,
                    std::vector<std::string>* warnings = nullptr);

// Every parameter loadNodeConfig reads ("group/name", sorted): the README's table is
// checked against it.
std::vector<std::string> nodeParameterNames();

// The runtime-safe parameters (cfg/Coral.cfg) <-> NodeConfig; R is the generated
// dynamic_reconfigure struct (coral_introspection::CoralConfig).
template <class R>
R toReconfigure(const NodeConfig& c) {
  R r;
  r.classifier_threshold = c.online.verdict.classifier.threshold;
  r.coral_radius = c.online.coral.radius;
  r.coral_min_overlap = c.online.coral.min_overlap;
  r.publish_quality_cloud = c.publish_quality_cloud;
  r.publish_features = c.publish_features;
  return r;
}
template <class R>
void applyReconfigure(const R& r, NodeConfig* c) {
  c->online.verdict.classifier.threshold = r.classifier_threshold;
  c->online.coral.radius = r.coral_radius;
  c->online.coral.min_overlap = r.coral_min_overlap;
  c->publish_quality_cloud = r.publish_quality_cloud;
  c->publish_features = r.publish_features;
}

}  // namespace ros_adapters
}  // namespace coral_introspection
