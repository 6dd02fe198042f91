#include "coral_introspection/rio/config_yaml.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "coral_introspection/coral/validation.hpp"
#include "coral_introspection/rio/config_keys.hpp"

namespace coral_introspection {
namespace rio {

namespace {

class Reader {
 public:
  explicit Reader(const YAML::Node& root) : root_(root) {}

  // The node at "group/key" (or "key"); undefined when absent.
  YAML::Node find(const std::string& path) {
    used_.insert(path);
    const std::size_t slash = path.find('/');
    if (!root_.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    if (slash == std::string::npos) return root_[path];
    const YAML::Node g = root_[path.substr(0, slash)];
    if (!g.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    return g[path.substr(slash + 1)];
  }
  template <class T>
  bool get(const std::string& path, T* out, const char* expected) {
    const YAML::Node n = find(path);
    if (!n.IsDefined() || n.IsNull()) return true;
    try {
      *out = n.as<T>();
    } catch (const YAML::Exception&) {
      return typeError(path, expected);
    }
    return true;
  }
  bool get(const std::string& path, double* v) { return get(path, v, "a number"); }
  bool get(const std::string& path, int* v) { return get(path, v, "an integer"); }
  bool get(const std::string& path, bool* v) { return get(path, v, "a bool (true/false)"); }
  bool get(const std::string& path, std::string* v) { return get(path, v, "a string"); }
  bool getVector(const std::string& path, std::size_t n, std::vector<double>* v) {
    const YAML::Node node = find(path);
    if (!node.IsDefined() || node.IsNull()) return true;
    if (!node.IsSequence() || node.size() != n)
      return typeError(path, ("a list of " + std::to_string(n) + " numbers").c_str());
    return get(path, v, "a list of numbers");
  }
  // Every key asked for so far ("group/key" or "key").
  std::vector<std::string> paths() const { return {used_.begin(), used_.end()}; }
  const std::string& error() const { return error_; }

 private:
  bool typeError(const std::string& path, const char* expected) {
    error_ = "parameter " + path + " must be " + expected;
    return false;
  }
  YAML::Node root_;
  std::set<std::string> used_;
  std::string error_;
};

bool readAll(Reader& r, RioConfig* c) {
  std::vector<double> t, q;
  std::string mode = toString(c->uncertainty.mode);
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
      r.getVector("extrinsics/translation", 3, &t) && r.getVector("extrinsics/rotation", 4, &q) &&
      r.get("radar_time_offset", &c->radar_time_offset) && r.get("uncertainty/mode", &mode) &&
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
  const std::vector<std::pair<const char*, UncertaintyMode>> modes = {
      {"full", UncertaintyMode::kFull},
      {"none", UncertaintyMode::kNone},
      {"no_range", UncertaintyMode::kNoRange},
      {"no_bearing", UncertaintyMode::kNoBearing}};
  for (const auto& [name, m] : modes)
    if (mode == name) {
      u.mode = m;
      return true;
    }
  return false;
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

bool load(const YAML::Node& root, RioConfig* cfg, std::string* error, const RioConfigRules& rules) {
  using core::fail;
  if (!root.IsDefined() || root.IsNull()) return fail(error, "the config is empty");
  if (!root.IsMap())
    return fail(error, "the config must be a map of groups (imu, extrinsics, ...)");
  // The valid keys are the ones readAll asks for (from an empty tree nothing fails).
  Reader probe{YAML::Node()};
  RioConfig defaults;
  readAll(probe, &defaults);
  const std::string unknown = unknownKeys(root, probe.paths(), rules.other_groups);
  if (!unknown.empty()) return fail(error, unknown);
  if (rules.require_extrinsics)
    for (const char* key : {"translation", "rotation"}) {
      const YAML::Node g = root["extrinsics"];  // const []: invalid (not null) when absent
      if (!g.IsDefined() || !g.IsMap() || !g[key] || g[key].IsNull())
        return fail(error, std::string("extrinsics/") + key +
                               " is required: the radar pose in the IMU (body) frame, "
                               "translation [x, y, z] m and rotation [qx, qy, qz, qw] (no "
                               "default: identity would be a guess)");
    }
  Reader r(root);
  if (!readAll(r, cfg))
    return fail(error, r.error().empty() ? "parameter uncertainty/mode must be one of full, "
                                           "none, no_range, no_bearing"
                                         : r.error());
  std::string dummy;
  if (error == nullptr) error = &dummy;
  *error = cfg->validate();
  return error->empty();
}

}  // namespace

bool loadRioConfig(const YAML::Node& root, RioConfig* cfg, std::string* error,
                   const RioConfigRules& rules) {
  try {
    return load(root, cfg, error, rules);
  } catch (const YAML::Exception& e) {  // a malformed tree the checks above did not foresee
    return core::fail(error, std::string("config: ") + e.what());
  }
}

bool applyOverride(YAML::Node& root, const std::string& assignment, std::string* error) {
  const std::size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) {
    if (error) *error = "override '" + assignment + "' is not key=value";
    return false;
  }
  const std::string key = assignment.substr(0, eq);
  YAML::Node value;
  try {
    value = YAML::Load(assignment.substr(eq + 1));
  } catch (const YAML::Exception& e) {
    if (error) *error = "override '" + assignment + "': " + e.what();
    return false;
  }
  try {
    const std::size_t slash = key.find('/');
    if (slash == std::string::npos)
      root[key] = value;
    else
      root[key.substr(0, slash)][key.substr(slash + 1)] = value;
  } catch (const YAML::Exception& e) {
    if (error) *error = "override '" + assignment + "': " + e.what();
    return false;
  }
  return true;
}

bool loadRioConfigFile(const std::string& path, RioConfig* cfg, std::string* error,
                       const RioConfigRules& rules) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    if (error) *error = "cannot read " + path + ": " + e.what();
    return false;
  }
  return loadRioConfig(root, cfg, error, rules);
}

}  // namespace rio
}  // namespace coral_introspection
