// One source of defaults: the dynamic_reconfigure ranges and defaults (cfg/Coral.cfg) equal
// the config structs' validate() ranges and defaults; every preset in config/ loads through
// the parameter loader as roslaunch would load it, sets only what differs from the defaults,
// and gives the same NodeConfig as the full presets it replaced.
#include <gtest/gtest.h>

#include <coral_introspection/CoralConfig.h>  // generated from cfg/Coral.cfg

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "coral_introspection/ros/coral_params.hpp"
#include "support/source_dir.hpp"

using namespace coral_introspection;
using ros_adapters::NodeConfig;
using Reconfigure = coral_introspection::CoralConfig;  // the generated dynamic_reconfigure class
using XmlRpc::XmlRpcValue;

namespace {

const double kInf = std::numeric_limits<double>::infinity();

// A reconfigurable double and the validate() of the struct it is copied into.
struct RangedParam {
  const char* name;
  double Reconfigure::*field;
  double struct_default;
  // Sets the value into a default struct and returns that struct's validate() message.
  std::function<std::string(double)> validate;
};

std::vector<RangedParam> rangedParams() {
  return {
      {"classifier_threshold", &Reconfigure::classifier_threshold,
       coral::ClassifierConfig().threshold,
       [](double v) {
         coral::ClassifierConfig c;
         c.threshold = v;
         return c.validate();
       }},
      {"coral_radius", &Reconfigure::coral_radius, coral::CoralConfig().radius,
       [](double v) {
         coral::CoralConfig c;
         c.radius = v;
         return c.validate();
       }},
      {"coral_min_overlap", &Reconfigure::coral_min_overlap, coral::CoralConfig().min_overlap,
       [](double v) {
         coral::CoralConfig c;
         c.min_overlap = v;
         return c.validate();
       }},
  };
}

TEST(ConfigDefaults, ReconfigureRangesEqualValidateRanges) {
  for (const auto& p : rangedParams()) {
    const double lo = Reconfigure::__getMin__().*p.field;
    const double hi = Reconfigure::__getMax__().*p.field;
    SCOPED_TRACE(std::string(p.name) + " in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                 "]");
    ASSERT_LT(lo, hi);
    // The .cfg boundaries are accepted, the next representable values outside rejected.
    EXPECT_EQ(p.validate(lo), "");
    EXPECT_EQ(p.validate(hi), "");
    EXPECT_NE(p.validate(std::nextafter(lo, -kInf)), "");
    EXPECT_NE(p.validate(std::nextafter(hi, kInf)), "");
  }
}

TEST(ConfigDefaults, ReconfigureDefaultsEqualStructDefaults) {
  const Reconfigure& d = Reconfigure::__getDefault__();
  for (const auto& p : rangedParams()) EXPECT_EQ(d.*p.field, p.struct_default) << p.name;
  EXPECT_EQ(d.publish_quality_cloud, NodeConfig().publish_quality_cloud);
  EXPECT_EQ(d.publish_features, NodeConfig().publish_features);
}

TEST(ConfigDefaults, EveryReconfigureParameterIsChecked) {
  // A parameter added to cfg/Coral.cfg must be added to the checks above.
  std::set<std::string> checked = {"publish_quality_cloud", "publish_features"};
  for (const auto& p : rangedParams()) checked.insert(p.name);
  std::set<std::string> in_cfg;
  for (const auto& d : Reconfigure::__getParamDescriptions__()) in_cfg.insert(d->name);
  EXPECT_EQ(in_cfg, checked);
}

// ---- presets ---------------------------------------------------------------------------

const std::string kSource = coral_test::sourceDir();

// Loads YAML files the way roslaunch's <rosparam command="load"> does (rosparam's YAML
// loader, later files merged key by key over earlier ones) and converts the tree through
// XML-RPC, the path parameters take from the parameter server to the nodelet.
XmlRpcValue loadYaml(const std::vector<std::string>& files) {
  std::string cmd =
      "/usr/bin/python3 -c '"
      "import sys, rosparam, xmlrpc.client\n"
      "def merge(a, b):\n"
      "    for k, v in b.items():\n"
      "        a[k] = merge(a.get(k, {}), v) if isinstance(v, dict) else v\n"
      "    return a\n"
      "tree = {}\n"
      "for f in sys.argv[1:]:\n"
      "    for params, ns in rosparam.load_file(f):\n"
      "        merge(tree, params)\n"
      "sys.stdout.write(xmlrpc.client.dumps((tree,)))\n"
      "'";
  for (const auto& f : files) cmd += " '" + f + "'";
  std::string xml;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) {
    ADD_FAILURE() << "cannot run " << cmd;
    return XmlRpcValue();
  }
  char buf[4096];
  for (std::size_t n; (n = fread(buf, 1, sizeof(buf), pipe)) > 0;) xml.append(buf, n);
  const int status = pclose(pipe);
  EXPECT_EQ(status, 0) << "rosparam could not load the YAML: " << cmd;
  int offset = static_cast<int>(xml.find("<value>"));
  if (offset < 0) {
    ADD_FAILURE() << "no XML-RPC value in: " << xml;
    return XmlRpcValue();
  }
  XmlRpcValue v(xml, &offset);
  EXPECT_EQ(v.getType(), XmlRpcValue::TypeStruct) << xml;
  return v;
}

// A list of numbers on one line, for describe().
std::string numbers(const std::vector<double>& v) {
  std::ostringstream s;
  s.precision(17);
  for (double x : v) s << x << ' ';
  return s.str();
}

// Every field of NodeConfig, one "name = value" line each (readable diffs).
std::string describe(const NodeConfig& c) {
  std::ostringstream s;
  s.precision(17);
  s << "input_type = " << static_cast<int>(c.input_type) << "\nfixed_frame = " << c.fixed_frame
    << "\nqueue_size = " << c.queue_size << "\ntf_timeout = " << c.tf_timeout
    << "\npairing.min_distance = " << c.online.pairing.min_distance
    << "\npairing.max_time_gap = " << c.online.pairing.max_time_gap
    << "\ncoral.dimension = " << c.online.coral.dimension
    << "\ncoral.radius = " << c.online.coral.radius
    << "\ncoral.dynamic_radius = " << c.online.coral.dynamic_radius
    << "\ncoral.r_min = " << c.online.coral.r_min << "\ncoral.r_max = " << c.online.coral.r_max
    << "\ncoral.alpha_deg = " << c.online.coral.alpha_deg
    << "\ncoral.epsilon = " << c.online.coral.epsilon
    << "\ncoral.e_reject = " << c.online.coral.e_reject
    << "\ncoral.min_neighbours = " << c.online.coral.min_neighbours
    << "\ncoral.min_neighbours_other = " << c.online.coral.min_neighbours_other
    << "\ncoral.aggregation = " << static_cast<int>(c.online.coral.aggregation)
    << "\ncoral.min_overlap = " << c.online.coral.min_overlap
    << "\ncoral.per_point = " << c.online.coral.per_point
    << "\ncoral.voxel_leaf = " << c.online.coral.voxel_leaf
    << "\ncoral.max_queries = " << c.online.coral.max_queries
    << "\ncoral.query_seed = " << c.online.coral.query_seed
    << "\ncoral.threads = " << c.online.coral.threads
    << "\ncoral.max_abs_coordinate = " << c.online.coral.max_abs_coordinate
    << "\ncoral.max_range = " << c.online.coral.max_range
    << "\ncoral.beam_step_deg = " << c.online.coral.beam_step_deg
    << "\ncoral.max_points = " << c.online.coral.max_points
    << "\ncoral.refuse_over_max_points = " << c.online.coral.refuse_over_max_points
    << "\ncoral.merge_distance = " << c.online.coral.merge_distance
    << "\ncoral.max_degenerate_fraction = " << c.online.coral.max_degenerate_fraction
    << "\nclassifier.beta0 = " << c.online.verdict.classifier.beta0
    << "\nclassifier.beta1 = " << c.online.verdict.classifier.beta1
    << "\nclassifier.beta2 = " << c.online.verdict.classifier.beta2
    << "\nclassifier.threshold = " << c.online.verdict.classifier.threshold
    << "\nclassifier.method = " << coral::verdictMethodName(c.online.verdict.method)
    << "\nclassifier.relative_margin = " << c.online.verdict.relative.margin
    << "\nclassifier.flat_ratio = " << c.online.verdict.relative.flat_ratio
    << "\nclassifier.probe_queries = " << c.online.verdict.relative.probe_queries
    << "\ngate.min_probability = " << c.online.verdict.gate.min_probability
    << "\ngate.min_overlap = " << c.online.verdict.gate.min_overlap
    << "\ngate.max_free_space = " << c.online.verdict.gate.max_free_space
    << "\ngate.min_constraint = " << c.online.verdict.gate.min_constraint
    << "\ngate.constraint_beam_step_deg = " << c.online.verdict.gate.constraint_beam_step_deg
    << "\ngate.max_quality = " << c.online.verdict.gate.max_quality
    << "\ngate.max_flat_axes = " << c.online.verdict.gate.max_flat_axes
    << "\ngate.coarse_max_multiple = " << c.online.verdict.gate.coarse_max_multiple
    << "\ngate.coarse_margin = " << c.online.verdict.gate.coarse_margin
    << "\ngate.coarse_below_probability = " << c.online.verdict.gate.coarse_below_probability
    << "\ngate.coarse_registration = " << c.online.verdict.gate.coarse_registration
    << "\ngate.coarse_min_registered_offset = "
    << c.online.verdict.gate.coarse_min_registered_offset
    << "\nloop_closure.min_probability = " << c.online.verdict.loop_closure.min_probability
    << "\nloop_closure.min_overlap = " << c.online.verdict.loop_closure.min_overlap
    << "\nloop_closure.relative_margin = " << c.online.verdict.loop_closure.relative_margin
    << "\nloop_closure.max_free_space = " << c.online.verdict.loop_closure.max_free_space
    << "\nloop_closure.min_constraint = " << c.online.verdict.loop_closure.min_constraint
    << "\nloop_closure.constraint_beam_step_deg = "
    << c.online.verdict.loop_closure.constraint_beam_step_deg
    << "\nloop_closure.max_quality = " << c.online.verdict.loop_closure.max_quality
    << "\nloop_closure.max_flat_axes = " << c.online.verdict.loop_closure.max_flat_axes
    << "\nloop_closure.coarse_max_multiple = " << c.online.verdict.loop_closure.coarse_max_multiple
    << "\nloop_closure.coarse_margin = " << c.online.verdict.loop_closure.coarse_margin
    << "\nloop_closure.coarse_below_probability = "
    << c.online.verdict.loop_closure.coarse_below_probability
    << "\nloop_closure.coarse_registration = " << c.online.verdict.loop_closure.coarse_registration
    << "\nloop_closure.coarse_min_registered_offset = "
    << c.online.verdict.loop_closure.coarse_min_registered_offset
    << "\nloop_closure.max_refinement = " << c.online.verdict.loop_closure.max_refinement
    << "\nloop_closure.restarts = " << c.online.verdict.loop_closure.restarts
    << "\nloop_closure.max_registered_offset = "
    << c.online.verdict.loop_closure.max_registered_offset
    << "\nloop_closure.registered_min_probability = "
    << c.online.verdict.loop_closure.registered_min_probability
    << "\nfree_space.bin_deg = " << c.online.verdict.free_space.bin_deg
    << "\nfree_space.margin = " << c.online.verdict.free_space.margin
    << "\nfree_space.min_tested = " << c.online.verdict.free_space.min_tested
    << "\nfree_space.min_extent = " << c.online.verdict.free_space.min_extent
    << "\nrestart.radii = " << numbers(c.online.verdict.restart.radii)
    << "\nrestart.directions = " << c.online.verdict.restart.directions
    << "\nrestart.min_distance = " << c.online.verdict.restart.min_distance
    << "\nrestart.max_q_ratio = " << c.online.verdict.restart.max_q_ratio
    << "\nrestart.min_overlap_ratio = " << c.online.verdict.restart.min_overlap_ratio
    << "\nrestart.coarse_points = " << c.online.verdict.restart.coarse_points
    << "\nrestart.coarse_min_step = " << c.online.verdict.restart.coarse_min_step
    << "\nrestart.coarse_back_within = " << c.online.verdict.restart.coarse_back_within
    << "\nrestart.coarse_same_within = " << c.online.verdict.restart.coarse_same_within
    << "\nregistration.max_correspondence = "
    << c.online.verdict.restart.registration.max_correspondence
    << "\nregistration.max_iterations = " << c.online.verdict.restart.registration.max_iterations
    << "\nregistration.min_step = " << c.online.verdict.restart.registration.min_step
    << "\nregistration.min_correspondences = "
    << c.online.verdict.restart.registration.min_correspondences
    << "\nregistration.normal_radius = " << c.online.verdict.restart.registration.normal_radius
    << "\nregistration.robust_scale = " << c.online.verdict.restart.registration.robust_scale
    << "\ncalibration.enabled = " << c.online.calibration.enabled
    << "\ncalibration.fraction_of_pairs = " << c.online.calibration.fraction_of_pairs
    << "\ncalibration.max_samples = " << c.online.calibration.max_samples
    << "\ncalibration.min_samples_before_use = " << c.online.calibration.min_samples_before_use
    << "\ncalibration.min_auc = " << c.online.calibration.min_auc
    << "\ncalibration.holdout_fraction = " << c.online.calibration.holdout_fraction
    << "\ncalibration.prior_weight = " << c.online.calibration.prior_weight
    << "\ncalibration.accept_score = " << c.online.calibration.accept_score
    << "\ncalibration.output_file = " << c.online.calibration.output_file
    << "\ntime_budget = " << c.time_budget << "\ntesting.pair_delay = " << c.testing_pair_delay
    << "\nheap_release_interval = " << c.heap_release_interval
    << "\ntolerance.translation = " << c.online.verdict.tolerance.translation
    << "\ntolerance.rotation_deg = " << c.online.verdict.tolerance.rotation_deg
    << "\npolar_format = " << static_cast<int>(c.polar_format)
    << "\npolar.range_resolution = " << c.polar.range_resolution
    << "\npolar.first_data_column = " << c.polar.first_data_column
    << "\npolar.num_azimuths = " << c.polar.num_azimuths
    << "\npolar.direction = " << static_cast<int>(c.polar.direction)
    << "\npolar.azimuth_offset_rad = " << c.polar.azimuth_offset_rad
    << "\npolar.scan_period = " << c.polar.scan_period << "\nrip.k = " << c.rip.k
    << "\nrip.z_min = " << c.rip.z_min << "\nrip.window = " << c.rip.window
    << "\nrip.min_range = " << c.rip.min_range << "\nrip.max_range = " << c.rip.max_range
    << "\ndeskew.enabled = " << c.online.deskew.enabled
    << "\ndeskew.window = " << c.online.deskew.window
    << "\npublish_quality_cloud = " << c.publish_quality_cloud
    << "\npublish_features = " << c.publish_features
    << "\ndoppler.enabled = " << c.online.doppler.enabled
    << "\ndoppler.velocity_field = " << c.velocity_field
    << "\ndoppler.sigma_doppler = " << c.online.doppler.check.sigma_doppler
    << "\ndoppler.ransac_threshold = " << c.online.doppler.check.ransac_threshold
    << "\ndoppler.ransac_iterations = " << c.online.doppler.check.ransac_iterations
    << "\ndoppler.min_inlier_ratio = " << c.online.doppler.check.min_inlier_ratio
    << "\ndoppler.min_points = " << c.online.doppler.check.min_points
    << "\ndoppler.confidence = " << c.online.doppler.check.confidence
    << "\ndoppler.radial_velocity_positive_away = "
    << c.online.doppler.check.radial_velocity_positive_away
    << "\ndoppler.seed = " << c.online.doppler.check.seed
    << "\ndoppler.sigma_reference_velocity = " << c.online.doppler.check.sigma_reference_velocity
    << "\ndoppler.point_covariances = " << c.online.doppler.point_covariances
    << "\ndoppler.noise.sigma_range = " << c.online.doppler.noise.sigma_range
    << "\ndoppler.noise.sigma_azimuth = " << c.online.doppler.noise.sigma_azimuth
    << "\ndoppler.noise.sigma_elevation = " << c.online.doppler.noise.sigma_elevation << "\n";
  return s.str();
}

NodeConfig load(const XmlRpcValue& tree, const std::string& what) {
  NodeConfig c;
  std::string err;  // also every unknown group or key
  EXPECT_TRUE(ros_adapters::loadNodeConfig(tree, &c, &err)) << what << ": " << err;
  return c;
}

// CoralNodelet presets: config/*.yaml except rio_*.yaml (RioNodelet settings, loaded and
// checked by rio::loadRioConfig).
std::vector<std::string> presetFiles() {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(kSource + "/config"))
    if (e.path().extension() == ".yaml" && e.path().filename().string().rfind("rio_", 0) != 0)
      files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

TEST(Presets, EveryPresetLoadsWithoutUnknownKeys) {
  const auto files = presetFiles();
  ASSERT_GE(files.size(), 5u);
  for (const auto& f : files) load(loadYaml({f}), f);
  // The trained classifier file loads over the preset it was trained with.
  const NodeConfig c = load(loadYaml({kSource + "/config/radar_oxford.yaml",
                                      kSource + "/config/classifier_radar_oxford.yaml"}),
                            "radar_oxford + classifier_radar_oxford");
  EXPECT_EQ(c.input_type, ros_adapters::InputType::kPolarImage);
  EXPECT_NEAR(c.online.verdict.classifier.beta1, -53.76,
              0.01);  // from the classifier file, not the preset
}

// The trimmed presets give exactly the NodeConfig of the full presets they replaced
// (recorded in test/ros/data/presets_before_trim/, every key spelled out).
TEST(Presets, TrimmedPresetsEqualTheFullOnes) {
  for (const char* name : {"lidar_2d", "lidar_3d", "radar_oxford", "radar_mulran"}) {
    SCOPED_TRACE(name);
    const std::string full = kSource + "/test/ros/data/presets_before_trim/" + name + ".yaml";
    const std::string trimmed = kSource + "/config/" + name + ".yaml";
    EXPECT_EQ(describe(load(loadYaml({trimmed}), trimmed)), describe(load(loadYaml({full}), full)));
  }
}

// Leaf paths ("coral/radius") of a parameter tree.
void leaves(const XmlRpcValue& v, const std::string& prefix, std::vector<std::string>* out) {
  if (v.getType() != XmlRpcValue::TypeStruct) {
    out->push_back(prefix);
    return;
  }
  for (auto it = v.begin(); it != v.end(); ++it)
    leaves(it->second, prefix.empty() ? it->first : prefix + "/" + it->first, out);
}

XmlRpcValue without(const XmlRpcValue& tree, const std::string& path) {
  XmlRpcValue copy;
  const std::size_t slash = path.find('/');
  for (auto it = tree.begin(); it != tree.end(); ++it) {
    if (slash == std::string::npos) {
      if (it->first != path) copy[it->first] = it->second;
    } else if (it->first == path.substr(0, slash)) {
      copy[it->first] = without(it->second, path.substr(slash + 1));
    } else {
      copy[it->first] = it->second;
    }
  }
  return copy;
}

// A preset lists only what differs: dropping any one of its keys changes the NodeConfig.
TEST(Presets, EveryPresetKeyDiffersFromTheDefault) {
  // Equal to the default but required: polar_image input refuses 3D CorAl (RIP features
  // are planar), so the radar presets must state coral/dimension: 2.
  // The tolerance is the user's statement of the error that matters: every preset states
  // it, even where it equals the default (issue: "tolerance in every preset").
  const std::set<std::string> explicit_on_purpose = {
      "radar_oxford.yaml:coral/dimension", "radar_mulran.yaml:coral/dimension",
      "lidar_3d.yaml:tolerance/translation", "lidar_3d.yaml:tolerance/rotation_deg",
      "lidar_2d.yaml:tolerance/translation"};
  for (const auto& f : presetFiles()) {
    const std::string base = std::filesystem::path(f).filename().string();
    // A trained classifier file carries all its keys: it is loaded over a preset and must
    // override that preset's classifier/* completely.
    if (base.rfind("classifier_", 0) == 0) continue;
    const XmlRpcValue tree = loadYaml({f});
    const std::string full = describe(load(tree, f));
    std::vector<std::string> keys;
    leaves(tree, "", &keys);
    EXPECT_GE(keys.size(), 3u) << base;
    for (const auto& k : keys) {
      if (explicit_on_purpose.count(base + ":" + k)) continue;
      EXPECT_TRUE(describe(load(without(tree, k), f + " without " + k)) != full)
          << base << ": " << k << " equals the default; drop it from the preset";
    }
  }
}

}  // namespace
