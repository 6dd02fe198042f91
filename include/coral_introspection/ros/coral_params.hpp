// Parameters of CoralNodelet: one struct holding every setting (defaults = the core and
// online config defaults), loaded from the private namespace and validated before anything
// starts. Loading reads a config::ParamTree (from the parameter server's XmlRpc tree, or from
// preset YAML files by the tools), so it is unit-tested without a ROS master and a preset
// means the same to coral_check as to the nodelet.
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

#include "coral_introspection/config/param_tree.hpp"

#include <string>
#include <vector>

#include "coral_introspection/online/introspector_config.hpp"
#include "coral_introspection/radar/polar_scan.hpp"
#include "coral_introspection/radar/rip_features.hpp"

namespace coral_introspection {
namespace ros_adapters {

// kLaserScan: sensor_msgs/LaserScan on `scan`, converted to planar points (coral/dimension 2).
enum class InputType { kPointCloud, kPolarImage, kLaserScan };
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
  // Polar and laser-scan input require coral/dimension 2 (RIP features and laser scans are
  // planar: 3D covariances of z = 0 points are singular), checked by validate() rather than
  // switched silently.
  online::IntrospectorConfig online;
  PolarFormat polar_format = PolarFormat::kOxford;
  radar::PolarImageConfig polar;  // used by polar_format plain (oxford: fixed layout)
  radar::RipConfig rip;
  bool publish_quality_cloud = true;
  bool publish_features = true;
  std::string velocity_field = "velocity";  // doppler/velocity_field: radial velocity [m/s]

  std::string validate() const;  // empty when valid; names the parameter, value and range
};
// Reads the parameter tree `params` into *cfg. Missing keys keep their defaults. Returns false
// with *error, in this order: a value of the wrong type (naming the parameter, its value and,
// from a file, "file:line"); every group or key that is not a parameter, each with the
// nearest valid name ("unknown group coarl (did you mean coral?)"); validate()'s message.
bool loadNodeConfig(config::ParamTree& params, NodeConfig* cfg, std::string* error);
// The same from the private namespace's XmlRpc tree (a struct, e.g. from
// nh.getParam(pnh.getNamespace(), v); an invalid/empty value means "no parameters set").
// `also_accepted`: keys that live in the namespace but are not NodeConfig's (CoralNodelet's
// dynamic_reconfigure values, ...), never unknown.
bool loadNodeConfig(const XmlRpc::XmlRpcValue& params, NodeConfig* cfg, std::string* error,
                    const std::vector<std::string>& also_accepted = {});

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
