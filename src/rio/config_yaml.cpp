#include "coral_introspection/rio/config_yaml.hpp"

#include <algorithm>
#include <cmath>

#include "coral_introspection/config/yaml_tree.hpp"
#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace rio {

namespace {

bool readAll(config::ParamTree& r, RioConfig* c) {
  std::vector<double> t, q;
  const std::vector<UncertaintyMode> modes = {UncertaintyMode::kFull, UncertaintyMode::kNone,
                                              UncertaintyMode::kNoRange,
                                              UncertaintyMode::kNoBearing};
  std::vector<std::string> mode_names;
  for (UncertaintyMode m : modes) mode_names.push_back(toString(m));
  int mode =
      static_cast<int>(std::find(modes.begin(), modes.end(), c->uncertainty.mode) - modes.begin());
  ImuNoiseConfig& imu = c->imu;
  UncertaintyConfig& u = c->uncertainty;
  FrontEndConfig& fe = c->front_end;
  AssociationConfig& a = c->association;
  SolverConfig& s = c->solver;
  InitConfig& in = c->init;
  ZeroVelocityConfig& zv = c->zero_velocity;
  HealthConfig& h = c->health;
  const bool ok =
      r.get("imu/acc_noise", &imu.acc_noise) && r.get("imu/gyro_noise", &imu.gyro_noise) &&
      r.get("imu/acc_bias_walk", &imu.acc_bias_walk) &&
      r.get("imu/gyro_bias_walk", &imu.gyro_bias_walk) && r.get("imu/gravity", &imu.gravity) &&
      r.getList("extrinsics/translation", 3, &t) && r.getList("extrinsics/rotation", 4, &q) &&
      r.get("radar_time_offset", &c->radar_time_offset) &&
      r.get("time_offset/estimate", &c->time_offset.estimate) &&
      r.get("time_offset/sigma", &c->time_offset.sigma) &&
      r.get("time_offset/max_abs", &c->time_offset.max_abs) &&
      r.get("time_offset/max_time_at_bound", &c->time_offset.max_time_at_bound) &&
      r.get("time_offset/max_latency", &c->time_offset.max_latency) &&
      r.getChoice("uncertainty/mode", mode_names, &mode) &&
      r.get("uncertainty/sigma_range", &u.noise.sigma_range) &&
      r.get("uncertainty/sigma_azimuth", &u.noise.sigma_azimuth) &&
      r.get("uncertainty/sigma_elevation", &u.noise.sigma_elevation) &&
      r.get("uncertainty/covariance_scale", &u.covariance_scale) &&
      r.get("uncertainty/isotropic_sigma", &u.isotropic_sigma) &&
      r.get("uncertainty/ablation_replace", &u.ablation_replace) &&
      r.get("uncertainty/ablation_shrink", &u.ablation_shrink) &&
      r.get("uncertainty/sigma_doppler", &u.sigma_doppler) &&
      r.get("uncertainty/doppler_sigma_isotropic", &u.doppler_sigma_isotropic) &&
      r.get("uncertainty/min_variance", &u.min_variance) &&
      r.get("front_end/min_range", &fe.min_range) && r.get("front_end/max_range", &fe.max_range) &&
      r.get("front_end/max_azimuth", &fe.max_azimuth) &&
      r.get("front_end/max_elevation", &fe.max_elevation) &&
      r.get("front_end/min_intensity", &fe.min_intensity) &&
      r.get("front_end/ransac_threshold", &fe.doppler.ransac_threshold) &&
      r.get("front_end/ransac_iterations", &fe.doppler.ransac_iterations) &&
      r.get("front_end/min_inlier_ratio", &fe.doppler.min_inlier_ratio) &&
      r.get("front_end/min_points", &fe.doppler.min_points) &&
      r.get("front_end/static_threshold", &fe.static_threshold) &&
      r.get("front_end/zero_velocity_speed", &fe.zero_velocity_speed) &&
      r.get("front_end/zero_velocity_min_points", &fe.zero_velocity_min_points) &&
      r.get("front_end/radial_velocity_positive_away", &fe.radial_velocity_positive_away) &&
      r.get("association/gate_sigma", &a.gate_sigma) &&
      r.get("association/max_search_radius", &a.max_search_radius) &&
      r.get("association/min_observations", &a.min_observations) &&
      r.get("association/max_map_landmarks", &a.max_map_landmarks) &&
      r.get("association/map_landmarks", &a.map_landmarks) &&
      r.get("association/outlier_chi2", &a.outlier_chi2) &&
      r.get("solver/window_size", &s.window_size) &&
      r.get("solver/max_iterations", &s.max_iterations) &&
      r.get("solver/max_solver_time", &s.max_solver_time) && r.get("solver/loss", &s.loss) &&
      r.get("solver/loss_scale", &s.loss_scale) && r.get("solver/use_doppler", &s.use_doppler) &&
      r.get("solver/use_points", &s.use_points) && r.get("solver/marginalize", &s.marginalize) &&
      r.get("init/static_duration", &in.static_duration) &&
      r.get("init/max_gyro_std", &in.max_gyro_std) && r.get("init/max_acc_std", &in.max_acc_std) &&
      r.get("init/timeout", &in.timeout) && r.get("init/sigma_roll_pitch", &in.sigma_roll_pitch) &&
      r.get("init/sigma_velocity", &in.sigma_velocity) &&
      r.get("init/sigma_acc_bias", &in.sigma_acc_bias) &&
      r.get("init/sigma_gyro_bias", &in.sigma_gyro_bias) &&
      r.get("zero_velocity/enabled", &zv.enabled) &&
      r.get("zero_velocity/sigma_velocity", &zv.sigma_velocity) &&
      r.get("zero_velocity/max_gyro_std", &zv.max_gyro_std) &&
      r.get("zero_velocity/max_gyro_rate", &zv.max_gyro_rate) &&
      r.get("zero_velocity/min_gyro_samples", &zv.min_gyro_samples) &&
      r.get("health/max_speed", &h.max_speed) && r.get("health/max_acc_bias", &h.max_acc_bias) &&
      r.get("health/max_gyro_bias", &h.max_gyro_bias) &&
      r.get("health/max_correction", &h.max_correction) &&
      r.get("health/max_imu_gap", &h.max_imu_gap) &&
      r.get("barometer/enabled", &c->barometer.enabled) &&
      r.get("barometer/sigma", &c->barometer.sigma) &&
      r.get("barometer/bias_walk", &c->barometer.bias_walk);
  if (!ok) return false;
  if (t.size() == 3) c->extrinsics.t = Vec3(t[0], t[1], t[2]);
  if (q.size() == 4) {
    const Quat qq(q[3], q[0], q[1], q[2]);
    // A quaternion that is not unit is rejected (validate() reports the rotation) rather
    // than silently normalised into a different rotation.
    c->extrinsics.R = std::abs(qq.norm() - 1.0) > 1e-3 ? Mat3::Constant(std::nan(""))
                                                       : qq.normalized().toRotationMatrix();
  }
  u.mode = modes[static_cast<std::size_t>(mode)];
  return true;
}

}  // namespace

const char* toString(UncertaintyMode m) {
  switch (m) {
    case UncertaintyMode::kFull:
      return "full";
    case UncertaintyMode::kNone:
      return "none";
    case UncertaintyMode::kNoRange:
      return "no_range";
    case UncertaintyMode::kNoBearing:
      return "no_bearing";
  }
  return "?";
}

namespace {

bool load(config::ParamTree& tree, RioConfig* cfg, std::string* error,
          const RioConfigRules& rules) {
  using coral::fail;
  if (tree.empty()) return fail(error, tree.origin() + "the config is empty");
  for (const std::string& g : rules.other_groups) tree.accept(g);
  if (!readAll(tree, cfg)) return fail(error, tree.error());
  // A key nobody read would otherwise leave its setting at the default (a misspelt
  // "extrinsic:" once meant identity extrinsics with nothing but a warning).
  if (const std::string unknown = tree.unknownKeysMessage(); !unknown.empty())
    return fail(error, unknown);
  if (rules.require_extrinsics)
    for (const char* key : {"translation", "rotation"})
      if (!tree.has(std::string("extrinsics/") + key))
        return fail(error, tree.origin() + "extrinsics/" + key +
                               " is required: the radar pose in the IMU (body) frame, "
                               "translation [x, y, z] m and rotation [qx, qy, qz, qw] (no "
                               "default: identity would be a guess)");
  const std::string invalid = cfg->validate();
  return invalid.empty() || fail(error, tree.origin() + invalid);
}

}  // namespace

bool loadRioConfig(config::ParamTree& tree, RioConfig* cfg, std::string* error,
                   const RioConfigRules& rules) {
  return load(tree, cfg, error, rules);
}

bool loadRioConfig(const YAML::Node& root, RioConfig* cfg, std::string* error,
                   const RioConfigRules& rules) {
  if (root.IsDefined() && !root.IsNull() && !root.IsMap())
    return coral::fail(error, "the config must be a map of groups (imu, extrinsics, ...)");
  config::ParamTree tree;
  return config::fromYaml(root, &tree, error) && load(tree, cfg, error, rules);
}

bool applyOverride(config::ParamTree& tree, const std::string& assignment, std::string* error) {
  const std::size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    return coral::fail(error, "override '" + assignment + "' is not key=value");
  // The value as YAML, typed exactly like a value in the file ({v: <value>} read as a tree).
  config::ParamTree value;
  if (!config::parseYaml("v: " + assignment.substr(eq + 1), &value, error))
    return coral::fail(error, "override '" + assignment + "': " + *error);
  config::ParamNode node = *value.root().child("v");
  node.where = "--set " + assignment;  // messages about it name the override, not the file
  tree.set(assignment.substr(0, eq), node);
  return true;
}

bool loadRioConfigFile(const std::string& path, RioConfig* cfg, std::string* error,
                       const RioConfigRules& rules) {
  config::ParamTree tree;
  return config::loadYamlFile(path, &tree, error) && load(tree, cfg, error, rules);
}

}  // namespace rio
}  // namespace coral_introspection
