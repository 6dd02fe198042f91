#include "coral_introspection/ros/params.hpp"

#include <xmlrpcpp/XmlRpcException.h>

#include <cmath>
#include <set>
#include <sstream>

namespace coral_introspection {
namespace ros_adapters {

namespace {

using XmlRpc::XmlRpcValue;

// Looks parameters up by "group/name" in the private tree; remembers which keys were read.
class Reader {
 public:
  explicit Reader(const XmlRpcValue& root) : root_(root) {}

  // Returns the value at path or nullptr when absent.
  const XmlRpcValue* find(const std::string& path) {
    used_.insert(path);
    const XmlRpcValue* v = &root_;
    std::size_t start = 0;
    while (true) {
      const std::size_t slash = path.find('/', start);
      const std::string key =
          path.substr(start, slash == std::string::npos ? slash : slash - start);
      if (v->getType() != XmlRpcValue::TypeStruct || !v->hasMember(key)) return nullptr;
      v = &(*v)[key];
      if (slash == std::string::npos) return v;
      start = slash + 1;
    }
  }

  bool get(const std::string& path, double* out) {
    const XmlRpcValue* v = find(path);
    if (v == nullptr) return true;
    if (v->getType() == XmlRpcValue::TypeDouble)
      *out = static_cast<double>(*v);
    else if (v->getType() == XmlRpcValue::TypeInt)
      *out = static_cast<int>(*v);
    else
      return typeError(path, "a number");
    return true;
  }
  bool get(const std::string& path, int* out) {
    const XmlRpcValue* v = find(path);
    if (v == nullptr) return true;
    if (v->getType() == XmlRpcValue::TypeInt) {
      *out = static_cast<int>(*v);
      return true;
    }
    if (v->getType() == XmlRpcValue::TypeDouble) {  // 12.0 is fine, 12.5 is not
      const double d = static_cast<double>(*v);
      if (d == std::round(d) && std::abs(d) < 1e9) {
        *out = static_cast<int>(d);
        return true;
      }
    }
    return typeError(path, "an integer");
  }
  bool get(const std::string& path, bool* out) {
    const XmlRpcValue* v = find(path);
    if (v == nullptr) return true;
    if (v->getType() != XmlRpcValue::TypeBoolean) return typeError(path, "a bool (true/false)");
    *out = static_cast<bool>(*v);
    return true;
  }
  bool get(const std::string& path, std::string* out) {
    const XmlRpcValue* v = find(path);
    if (v == nullptr) return true;
    if (v->getType() != XmlRpcValue::TypeString) return typeError(path, "a string");
    *out = static_cast<std::string>(*v);
    return true;
  }
  // String parameter restricted to `allowed`; *index = position in allowed.
  bool getChoice(const std::string& path, const std::vector<std::string>& allowed, int* index) {
    std::string s = allowed[*index];
    if (!get(path, &s)) return false;
    for (std::size_t i = 0; i < allowed.size(); ++i)
      if (s == allowed[i]) {
        *index = static_cast<int>(i);
        return true;
      }
    std::ostringstream e;
    e << "parameter ~" << path << " = '" << s << "' is not one of:";
    for (const auto& a : allowed) e << " " << a;
    error_ = e.str();
    return false;
  }
  bool has(const std::string& path) { return find(path) != nullptr; }

  // Keys in the given groups that no get() asked for.
  void unknownKeys(const std::vector<std::string>& groups, std::vector<std::string>* out) {
    for (const auto& g : groups) {
      if (root_.getType() != XmlRpcValue::TypeStruct || !root_.hasMember(g)) continue;
      const XmlRpcValue& grp = root_[g];
      if (grp.getType() != XmlRpcValue::TypeStruct) continue;
      for (auto it = grp.begin(); it != grp.end(); ++it)
        if (!used_.count(g + "/" + it->first))
          out->push_back("unknown parameter ~" + g + "/" + it->first + " (ignored)");
    }
  }
  const std::string& error() const { return error_; }

 private:
  bool typeError(const std::string& path, const char* expected) {
    error_ = "parameter ~" + path + " must be " + expected;
    return false;
  }
  const XmlRpcValue& root_;
  std::set<std::string> used_;
  std::string error_;
};

bool readAll(Reader& r, NodeConfig* c) {
  int input = c->input_type == InputType::kPolarImage ? 1 : 0;
  if (!r.getChoice("input_type", {"pointcloud", "polar_image"}, &input)) return false;
  c->input_type = input == 1 ? InputType::kPolarImage : InputType::kPointCloud;
  // Radar features are planar: 2D CorAl unless the user insists.
  if (c->input_type == InputType::kPolarImage && !r.has("coral/dimension")) c->coral.dimension = 2;
  int agg = c->coral.aggregation == core::Aggregation::kMedian ? 1 : 0;
  int fmt = c->polar_format == PolarFormat::kPlain ? 1 : 0;
  int dir = c->polar.direction == core::AzimuthDirection::kClockwise ? 1 : 0;
  const bool ok =
      r.get("fixed_frame", &c->fixed_frame) && r.get("queue_size", &c->queue_size) &&
      r.get("tf_timeout", &c->tf_timeout) &&
      r.get("pairing/min_distance", &c->pairing.min_distance) &&
      r.get("pairing/max_time_gap", &c->pairing.max_time_gap) &&
      r.get("coral/dimension", &c->coral.dimension) && r.get("coral/radius", &c->coral.radius) &&
      r.get("coral/dynamic_radius", &c->coral.dynamic_radius) &&
      r.get("coral/r_min", &c->coral.r_min) && r.get("coral/r_max", &c->coral.r_max) &&
      r.get("coral/alpha_deg", &c->coral.alpha_deg) && r.get("coral/epsilon", &c->coral.epsilon) &&
      r.get("coral/e_reject", &c->coral.e_reject) &&
      r.get("coral/min_neighbours", &c->coral.min_neighbours) &&
      r.get("coral/min_neighbours_other", &c->coral.min_neighbours_other) &&
      r.getChoice("coral/aggregation", {"mean", "median"}, &agg) &&
      r.get("coral/min_overlap", &c->coral.min_overlap) &&
      r.get("coral/voxel_leaf", &c->coral.voxel_leaf) &&
      r.get("coral/max_queries", &c->coral.max_queries) &&
      r.get("coral/query_seed", &c->coral.query_seed) &&
      r.get("coral/threads", &c->coral.threads) &&
      r.get("coral/max_abs_coordinate", &c->coral.max_abs_coordinate) &&
      r.get("coral/max_points", &c->coral.max_points) &&
      r.get("coral/refuse_over_max_points", &c->coral.refuse_over_max_points) &&
      r.get("coral/merge_distance", &c->coral.merge_distance) &&
      r.get("coral/max_degenerate_fraction", &c->coral.max_degenerate_fraction) &&
      r.get("classifier/beta0", &c->classifier.beta0) &&
      r.get("classifier/beta1", &c->classifier.beta1) &&
      r.get("classifier/beta2", &c->classifier.beta2) &&
      r.get("classifier/threshold", &c->classifier.threshold) &&
      r.getChoice("radar/polar_format", {"oxford", "plain"}, &fmt) &&
      r.get("radar/range_resolution", &c->polar.range_resolution) &&
      r.get("radar/first_data_column", &c->polar.first_data_column) &&
      r.get("radar/num_azimuths", &c->polar.num_azimuths) &&
      r.getChoice("radar/azimuth_direction", {"ccw", "cw"}, &dir) &&
      r.get("radar/azimuth_offset", &c->polar.azimuth_offset_rad) &&
      r.get("radar/scan_period", &c->polar.scan_period) && r.get("rip/k", &c->rip.k) &&
      r.get("rip/z_min", &c->rip.z_min) && r.get("rip/window", &c->rip.window) &&
      r.get("rip/min_range", &c->rip.min_range) && r.get("rip/max_range", &c->rip.max_range) &&
      r.get("motion_compensation/enabled", &c->motion_compensation) &&
      r.get("publish/quality_cloud", &c->publish_quality_cloud) &&
      r.get("publish/features", &c->publish_features) &&
      r.get("doppler/enabled", &c->doppler.enabled) &&
      r.get("doppler/velocity_field", &c->doppler.velocity_field) &&
      r.get("doppler/sigma_doppler", &c->doppler.check.sigma_doppler) &&
      r.get("doppler/ransac_threshold", &c->doppler.check.ransac_threshold) &&
      r.get("doppler/ransac_iterations", &c->doppler.check.ransac_iterations) &&
      r.get("doppler/min_inlier_ratio", &c->doppler.check.min_inlier_ratio) &&
      r.get("doppler/min_points", &c->doppler.check.min_points) &&
      r.get("doppler/confidence", &c->doppler.check.confidence) &&
      r.get("doppler/radial_velocity_positive_away",
            &c->doppler.check.radial_velocity_positive_away) &&
      r.get("doppler/sigma_reference_velocity", &c->doppler.check.sigma_reference_velocity);
  c->coral.aggregation = agg == 1 ? core::Aggregation::kMedian : core::Aggregation::kMean;
  c->polar_format = fmt == 1 ? PolarFormat::kPlain : PolarFormat::kOxford;
  c->polar.direction =
      dir == 1 ? core::AzimuthDirection::kClockwise : core::AzimuthDirection::kCounterClockwise;
  return ok;
}

}  // namespace

std::string NodeConfig::validate() const {
  std::ostringstream e;
  auto add = [&e](const std::string& group, const std::string& msg) {
    if (msg.empty()) return;
    if (!e.str().empty()) e << "; ";
    e << group << msg;
  };
  if (fixed_frame.empty()) add("", "fixed_frame must not be empty");
  if (queue_size < 1 || queue_size > 1000)
    add("", "queue_size must be in [1, 1000] (got " + std::to_string(queue_size) + ")");
  if (!(tf_timeout > 0.0 && tf_timeout <= 60.0))
    add("", "tf_timeout must be in (0, 60] s (got " + std::to_string(tf_timeout) + ")");
  add("", pairing.validate());
  add("~coral/", coral.validate());
  add("~classifier/", classifier.validate());
  if (input_type == InputType::kPolarImage) {
    if (polar_format == PolarFormat::kPlain) add("~radar/", polar.validate());
    add("~rip/", rip.validate());
  }
  if (doppler.enabled) {
    if (doppler.velocity_field.empty())
      add("", "doppler/velocity_field must not be empty when doppler/enabled");
    add("~doppler/", doppler.check.validate());
  }
  return e.str();
}

bool loadNodeConfig(const XmlRpc::XmlRpcValue& params, NodeConfig* cfg, std::string* error,
                    std::vector<std::string>* warnings) {
  std::string dummy;
  if (error == nullptr) error = &dummy;
  try {
    Reader r(params);
    if (!readAll(r, cfg)) {
      *error = r.error();
      return false;
    }
    if (warnings)
      r.unknownKeys({"pairing", "coral", "classifier", "radar", "rip", "motion_compensation",
                     "publish", "doppler"},
                    warnings);
  } catch (const XmlRpc::XmlRpcException& e) {
    *error = std::string("malformed parameter tree: ") + e.getMessage();
    return false;
  }
  *error = cfg->validate();
  return error->empty();
}

}  // namespace ros_adapters
}  // namespace coral_introspection
