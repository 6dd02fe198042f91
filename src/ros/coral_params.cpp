#include "coral_introspection/ros/coral_params.hpp"

#include <sstream>

#include "coral_introspection/ros/xmlrpc_tree.hpp"

namespace coral_introspection {
namespace ros_adapters {

namespace {

// Indexed by coral::VerdictMethod.
std::vector<std::string> methodNames() {
  std::vector<std::string> n;
  for (auto m : {coral::VerdictMethod::kClassifier, coral::VerdictMethod::kRelative,
                 coral::VerdictMethod::kBoth, coral::VerdictMethod::kGated})
    n.push_back(coral::verdictMethodName(m));
  return n;
}

bool readAll(config::ParamTree& r, NodeConfig* c) {
  online::IntrospectorConfig& o = c->online;
  int input = static_cast<int>(c->input_type);  // InputType order
  int agg = o.coral.aggregation == coral::Aggregation::kMedian ? 1 : 0;
  int fmt = c->polar_format == PolarFormat::kPlain ? 1 : 0;
  int dir = c->polar.direction == radar::AzimuthDirection::kClockwise ? 1 : 0;
  int seed = static_cast<int>(o.doppler.check.seed);
  int method = static_cast<int>(o.verdict.method);  // coral::VerdictMethod order
  coral::RestartConfig& rs = o.verdict.restart;     // restart/, registration/
  int coarse_points = static_cast<int>(rs.coarse_points);
  const bool ok =
      r.getChoice("input_type", {"pointcloud", "polar_image", "laser_scan"}, &input) &&
      r.get("fixed_frame", &c->fixed_frame) && r.get("queue_size", &c->queue_size) &&
      r.get("tf_timeout", &c->tf_timeout) && r.get("time_budget", &c->time_budget) &&
      r.get("testing/pair_delay", &c->testing_pair_delay) &&
      r.get("heap_release_interval", &c->heap_release_interval) &&
      r.get("pairing/min_distance", &o.pairing.min_distance) &&
      r.get("pairing/max_time_gap", &o.pairing.max_time_gap) &&
      r.get("coral/dimension", &o.coral.dimension) && r.get("coral/radius", &o.coral.radius) &&
      r.get("coral/dynamic_radius", &o.coral.dynamic_radius) &&
      r.get("coral/r_min", &o.coral.r_min) && r.get("coral/r_max", &o.coral.r_max) &&
      r.get("coral/alpha_deg", &o.coral.alpha_deg) && r.get("coral/epsilon", &o.coral.epsilon) &&
      r.get("coral/e_reject", &o.coral.e_reject) &&
      r.get("coral/min_neighbours", &o.coral.min_neighbours) &&
      r.get("coral/min_neighbours_other", &o.coral.min_neighbours_other) &&
      r.getChoice("coral/aggregation", {"mean", "median"}, &agg) &&
      r.get("coral/min_overlap", &o.coral.min_overlap) &&
      r.get("coral/voxel_leaf", &o.coral.voxel_leaf) &&
      r.get("coral/max_queries", &o.coral.max_queries) &&
      r.get("coral/query_seed", &o.coral.query_seed) && r.get("coral/threads", &o.coral.threads) &&
      r.get("coral/max_abs_coordinate", &o.coral.max_abs_coordinate) &&
      r.get("coral/max_range", &o.coral.max_range) &&
      r.get("coral/beam_step_deg", &o.coral.beam_step_deg) &&
      r.get("coral/max_points", &o.coral.max_points) &&
      r.get("coral/refuse_over_max_points", &o.coral.refuse_over_max_points) &&
      r.get("coral/merge_distance", &o.coral.merge_distance) &&
      r.get("coral/max_degenerate_fraction", &o.coral.max_degenerate_fraction) &&
      r.get("classifier/beta0", &o.verdict.classifier.beta0) &&
      r.get("classifier/beta1", &o.verdict.classifier.beta1) &&
      r.get("classifier/beta2", &o.verdict.classifier.beta2) &&
      r.get("classifier/threshold", &o.verdict.classifier.threshold) &&
      r.getChoice("classifier/method", methodNames(), &method) &&
      r.get("classifier/relative_margin", &o.verdict.relative.margin) &&
      r.get("classifier/flat_ratio", &o.verdict.relative.flat_ratio) &&
      r.get("classifier/probe_queries", &o.verdict.relative.probe_queries) &&
      r.get("gate/min_probability", &o.verdict.gate.min_probability) &&
      r.get("gate/min_overlap", &o.verdict.gate.min_overlap) &&
      r.get("gate/max_free_space", &o.verdict.gate.max_free_space) &&
      r.get("gate/min_constraint", &o.verdict.gate.min_constraint) &&
      r.get("gate/constraint_beam_step_deg", &o.verdict.gate.constraint_beam_step_deg) &&
      r.get("gate/max_quality", &o.verdict.gate.max_quality) &&
      r.get("gate/max_flat_axes", &o.verdict.gate.max_flat_axes) &&
      r.get("gate/coarse_max_multiple", &o.verdict.gate.coarse_max_multiple) &&
      r.get("gate/coarse_margin", &o.verdict.gate.coarse_margin) &&
      r.get("gate/coarse_below_probability", &o.verdict.gate.coarse_below_probability) &&
      r.get("gate/coarse_registration", &o.verdict.gate.coarse_registration) &&
      r.get("gate/coarse_min_registered_offset", &o.verdict.gate.coarse_min_registered_offset) &&
      r.get("loop_closure/min_probability", &o.verdict.loop_closure.min_probability) &&
      r.get("loop_closure/min_overlap", &o.verdict.loop_closure.min_overlap) &&
      r.get("loop_closure/relative_margin", &o.verdict.loop_closure.relative_margin) &&
      r.get("loop_closure/max_free_space", &o.verdict.loop_closure.max_free_space) &&
      r.get("loop_closure/min_constraint", &o.verdict.loop_closure.min_constraint) &&
      r.get("loop_closure/constraint_beam_step_deg",
            &o.verdict.loop_closure.constraint_beam_step_deg) &&
      r.get("loop_closure/max_quality", &o.verdict.loop_closure.max_quality) &&
      r.get("loop_closure/max_flat_axes", &o.verdict.loop_closure.max_flat_axes) &&
      r.get("loop_closure/coarse_max_multiple", &o.verdict.loop_closure.coarse_max_multiple) &&
      r.get("loop_closure/coarse_margin", &o.verdict.loop_closure.coarse_margin) &&
      r.get("loop_closure/coarse_below_probability",
            &o.verdict.loop_closure.coarse_below_probability) &&
      r.get("loop_closure/coarse_registration", &o.verdict.loop_closure.coarse_registration) &&
      r.get("loop_closure/coarse_min_registered_offset",
            &o.verdict.loop_closure.coarse_min_registered_offset) &&
      r.get("loop_closure/max_refinement", &o.verdict.loop_closure.max_refinement) &&
      r.get("loop_closure/restarts", &o.verdict.loop_closure.restarts) &&
      r.get("loop_closure/max_registered_offset", &o.verdict.loop_closure.max_registered_offset) &&
      r.get("loop_closure/registered_min_probability",
            &o.verdict.loop_closure.registered_min_probability) &&
      r.getList("restart/radii", 0, &rs.radii) && r.get("restart/directions", &rs.directions) &&
      r.get("restart/min_distance", &rs.min_distance) &&
      r.get("restart/max_q_ratio", &rs.max_q_ratio) &&
      r.get("restart/min_overlap_ratio", &rs.min_overlap_ratio) &&
      r.get("restart/coarse_points", &coarse_points) &&
      r.get("restart/coarse_min_step", &rs.coarse_min_step) &&
      r.get("restart/coarse_back_within", &rs.coarse_back_within) &&
      r.get("restart/coarse_same_within", &rs.coarse_same_within) &&
      r.get("registration/max_correspondence", &rs.registration.max_correspondence) &&
      r.get("registration/max_iterations", &rs.registration.max_iterations) &&
      r.get("registration/min_step", &rs.registration.min_step) &&
      r.get("registration/min_correspondences", &rs.registration.min_correspondences) &&
      r.get("registration/normal_radius", &rs.registration.normal_radius) &&
      r.get("registration/robust_scale", &rs.registration.robust_scale) &&
      r.get("free_space/bin_deg", &o.verdict.free_space.bin_deg) &&
      r.get("free_space/margin", &o.verdict.free_space.margin) &&
      r.get("free_space/min_tested", &o.verdict.free_space.min_tested) &&
      r.get("free_space/min_extent", &o.verdict.free_space.min_extent) &&
      r.get("tolerance/translation", &o.verdict.tolerance.translation) &&
      r.get("tolerance/rotation_deg", &o.verdict.tolerance.rotation_deg) &&
      r.getChoice("radar/polar_format", {"oxford", "plain"}, &fmt) &&
      r.get("radar/range_resolution", &c->polar.range_resolution) &&
      r.get("radar/first_data_column", &c->polar.first_data_column) &&
      r.get("radar/num_azimuths", &c->polar.num_azimuths) &&
      r.getChoice("radar/azimuth_direction", {"ccw", "cw"}, &dir) &&
      r.get("radar/azimuth_offset", &c->polar.azimuth_offset_rad) &&
      r.get("radar/scan_period", &c->polar.scan_period) && r.get("rip/k", &c->rip.k) &&
      r.get("rip/z_min", &c->rip.z_min) && r.get("rip/window", &c->rip.window) &&
      r.get("rip/min_range", &c->rip.min_range) && r.get("rip/max_range", &c->rip.max_range) &&
      r.get("motion_compensation/enabled", &o.deskew.enabled) &&
      r.get("publish/quality_cloud", &c->publish_quality_cloud) &&
      r.get("publish/features", &c->publish_features) &&
      r.get("doppler/enabled", &o.doppler.enabled) &&
      r.get("doppler/velocity_field", &c->velocity_field) &&
      r.get("doppler/sigma_doppler", &o.doppler.check.sigma_doppler) &&
      r.get("doppler/ransac_threshold", &o.doppler.check.ransac_threshold) &&
      r.get("doppler/ransac_iterations", &o.doppler.check.ransac_iterations) &&
      r.get("doppler/seed", &seed) &&
      r.get("doppler/min_inlier_ratio", &o.doppler.check.min_inlier_ratio) &&
      r.get("doppler/min_points", &o.doppler.check.min_points) &&
      r.get("doppler/confidence", &o.doppler.check.confidence) &&
      r.get("doppler/radial_velocity_positive_away",
            &o.doppler.check.radial_velocity_positive_away) &&
      r.get("doppler/sigma_reference_velocity", &o.doppler.check.sigma_reference_velocity) &&
      r.get("doppler/point_covariances", &o.doppler.point_covariances) &&
      r.get("doppler/sigma_range", &o.doppler.noise.sigma_range) &&
      r.get("doppler/sigma_azimuth", &o.doppler.noise.sigma_azimuth) &&
      r.get("doppler/sigma_elevation", &o.doppler.noise.sigma_elevation) &&
      r.get("calibration/enabled", &o.calibration.enabled) &&
      r.get("calibration/fraction_of_pairs", &o.calibration.fraction_of_pairs) &&
      r.get("calibration/max_samples", &o.calibration.max_samples) &&
      r.get("calibration/min_samples_before_use", &o.calibration.min_samples_before_use) &&
      r.get("calibration/min_auc", &o.calibration.min_auc) &&
      r.get("calibration/holdout_fraction", &o.calibration.holdout_fraction) &&
      r.get("calibration/prior_weight", &o.calibration.prior_weight) &&
      r.get("calibration/accept_score", &o.calibration.accept_score) &&
      r.get("calibration/output_file", &o.calibration.output_file);
  c->input_type = static_cast<InputType>(input);
  o.verdict.method = static_cast<coral::VerdictMethod>(method);
  o.coral.aggregation = agg == 1 ? coral::Aggregation::kMedian : coral::Aggregation::kMean;
  c->polar_format = fmt == 1 ? PolarFormat::kPlain : PolarFormat::kOxford;
  c->polar.direction =
      dir == 1 ? radar::AzimuthDirection::kClockwise : radar::AzimuthDirection::kCounterClockwise;
  if (!ok) return false;
  if (seed < 0)
    return r.fail("parameter doppler/seed must be >= 0 (got " + std::to_string(seed) + ")");
  o.doppler.check.seed = static_cast<unsigned>(seed);
  if (coarse_points < 0)
    return r.fail("parameter restart/coarse_points must be >= 0, 0 = off (got " +
                  std::to_string(coarse_points) + ")");
  rs.coarse_points = static_cast<std::size_t>(coarse_points);
  return true;
}

}  // namespace

std::string NodeConfig::validate() const {
  std::ostringstream e;
  auto add = [&e](const std::string& msg) {
    if (msg.empty()) return;
    if (!e.str().empty()) e << "; ";
    e << msg;
  };
  if (fixed_frame.empty()) add("fixed_frame must not be empty");
  if (queue_size < 1 || queue_size > 1000)
    add("queue_size must be in [1, 1000] (got " + std::to_string(queue_size) + ")");
  if (!(tf_timeout > 0.0 && tf_timeout <= 60.0))
    add("tf_timeout must be in (0, 60] s (got " + std::to_string(tf_timeout) + ")");
  if (!(time_budget >= 0.0 && time_budget <= 3600.0))
    add("time_budget must be in [0, 3600] s, 0 = off (got " + std::to_string(time_budget) + ")");
  if (!(heap_release_interval >= 0.0 && heap_release_interval <= 3600.0))
    add("heap_release_interval must be in [0, 3600] s, 0 = off (got " +
        std::to_string(heap_release_interval) + ")");
  if (!(testing_pair_delay >= 0.0 && testing_pair_delay <= 60.0))
    add("testing/pair_delay must be in [0, 60] s (got " + std::to_string(testing_pair_delay) + ")");
  add(online.validate());
  if (input_type == InputType::kPolarImage) {
    if (polar_format == PolarFormat::kPlain)
      add(online::prefixMessages("radar/", polar.validate()));
    add(online::prefixMessages("rip/", rip.validate()));
    // Explicit instead of switched silently: 3D entropies of planar (z = 0) features are
    // undefined, so such a config could never give a verdict.
    if (online.coral.dimension != 2)
      add("coral/dimension must be 2 for input_type polar_image (radar features are planar; got " +
          std::to_string(online.coral.dimension) + ")");
  }
  if (input_type == InputType::kLaserScan && online.coral.dimension != 2)
    add("coral/dimension must be 2 for input_type laser_scan (a laser scan is planar; got " +
        std::to_string(online.coral.dimension) + "): use config/lidar_2d.yaml");
  if (input_type == InputType::kLaserScan && online.doppler.enabled)
    add("doppler/enabled needs a radial-velocity field, which a LaserScan has not: use "
        "input_type pointcloud");
  if (online.doppler.enabled && velocity_field.empty())
    add("doppler/velocity_field must not be empty when doppler/enabled");
  return e.str();
}

std::vector<std::string> nodeParameterNames() {
  config::ParamTree probe;  // empty: every getter only records its name
  NodeConfig c;
  readAll(probe, &c);
  return probe.readPaths();
}

bool loadNodeConfig(config::ParamTree& params, NodeConfig* cfg, std::string* error) {
  std::string dummy;
  if (error == nullptr) error = &dummy;
  if (!readAll(params, cfg)) {
    *error = params.error();
    return false;
  }
  // An unknown group or key would leave its settings at the defaults without a word (a
  // misspelt `coarl:` turned a 0.5 m error into "aligned"): an error, never a warning.
  *error = params.unknownKeysMessage();
  if (!error->empty()) return false;
  const std::string invalid = cfg->validate();
  *error = invalid.empty() ? "" : params.origin() + invalid;
  return error->empty();
}

bool loadNodeConfig(const XmlRpc::XmlRpcValue& params, NodeConfig* cfg, std::string* error,
                    const std::vector<std::string>& also_accepted) {
  config::ParamTree tree;
  if (!fromXmlRpc(params, &tree, error)) return false;
  for (const std::string& key : also_accepted) tree.accept(key);
  return loadNodeConfig(tree, cfg, error);
}

}  // namespace ros_adapters
}  // namespace coral_introspection
