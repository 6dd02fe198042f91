// coral_train: self-supervised training and evaluation of the CorAl alignment classifier
// and the baselines (paper Sec. III-F, IV, V). Thin: argument parsing and progress only;
// the work is in core (oxford_training, training_set, evaluation, training_run).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "coral_introspection/eval/oxford_training.hpp"
#include "coral_introspection/eval/tool_args.hpp"
#include "coral_introspection/eval/training_run.hpp"
#include "coral_introspection/ros_eval/bag_training_reader.hpp"
#include "coral_introspection/ros_eval/verdict_training.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::radar;
using namespace coral_introspection::eval;
namespace ros_eval = coral_introspection::ros_eval;

namespace {

const char* kUsage =
    R"(Usage: rosrun coral_introspection coral_train --preset YAML (--dataset SPEC ... | --samples CSV ...)
                                                  [tolerance options]
       rosrun coral_introspection coral_train (--oxford DIR | --bag FILE) [paper protocol options]

Tolerance mode (--preset): trains and evaluates the preset's verdict at its tolerance
(tolerance/translation [m], tolerance/rotation_deg [deg]) with the preset's CorAl settings:
the trained classifier, the training-free relative check and their combination, in data set
(contiguous CV), cross data set and leave one data set out; writes report.md, roc.png,
verdict.yaml (the preset's tolerance + classifier sections, default method chosen by the
leave-one-out accuracy) and samples.csv.
  --preset YAML           sensor preset, e.g. config/lidar_3d.yaml
  --dataset [NAME=]KIND:PATH   repeatable; KIND: oxford DIR | keyframes DIR (Scans/*.pcd +
                          optimized_poses.txt) | carmen FILE.clf[.bz2] (+ .relations) |
                          cloudlist FILE (name + 4x4 pose per line) | bag FILE (--scan_topic,
                          --odom_topic, --fixed_frame)
  --samples CSV           repeatable; fit from sample files (e.g. the shards) instead
  --shard I/N             compute only pairs with index % N == I and write
                          samples_shardIofN.csv (for a job array / GNU parallel), e.g.
                            parallel coral_train --preset P --dataset D --shard {}/8 \
                              --output shards ::: 0 1 2 3 4 5 6 7
                            coral_train --preset P --samples shards/samples_shard0of8.csv \
                              ... --samples shards/samples_shard7of8.csv --output report
  --threads N             worker threads; 0 = every core                    [0]
  --relative_margin M     relative-check margin instead of the preset's
  --aligned_spread F      also label aligned the poses F tolerances off along each axis
                          (F in [0, 1); a registration stops short of the exact pose)  [0]
  --max_scans N  --folds K  --output DIR  --no_csv   as below

Builds aligned scan pairs from accurate poses, induces misalignments in the sensor frame of
the later scan (T_a_b' = T_a_b * Delta), computes CorAl, CorAl-median, MME, NDT, Rel-NDT and
CFEAR-P2P/P2L/P2D for every sample, evaluates a logistic-regression classifier per method
and error magnitude on held-out pairs and writes the deployable CorAl classifier.

Input:
  --oxford DIR            Oxford Radar RobotCar folder (radar/*.png, radar.timestamps,
                          gt/radar_odometry.csv)
  --bag FILE              rosbag with a scan topic and accurate poses
  --scan_topic T          PointCloud2 or polar radar Image topic in the bag  [/scan]
  --odom_topic T          nav_msgs/Odometry topic with the poses; empty = /tf [""]
  --fixed_frame F         frame the scan poses are looked up in              [odom]
  --test_oxford DIR / --test_bag FILE
                          train on the first input, test on this one (generalization
                          test) instead of cross-validation
  --sensor S              radar | lidar3d | lidar2d: method settings and default protocol
                          [radar for --oxford and polar images, else lidar3d]
  --max_scans N           use only the first N scans (0 = all)            [0]
  --spacing M             min distance between paired scans [m]; 0 = consecutive [0]
Protocol:
  --magnitudes LIST       translation offsets [m], 4 per pair (fwd/back/left/right)
                          [radar 0.3,0.5,0.7; lidar 0.1]
  --rotations LIST        pure yaw offsets +-theta [rad], 2 per pair       []
  --combined_yaw RAD      yaw added to every translation offset [radar 0; lidar 0.1]
Methods:
  --radius M              CorAl radius r [m]; NDT voxel = 2 r
                          [radar 1.0, lidar3d 0.3, lidar2d 0.5]
  --k N  --z_min Z        RIP k-strongest k and noise floor                 [12, 70]
  --window W              RIP window w                                      [2]
  --min_range M           features closer than this are dropped [m]         [2.5]
  --cfear_z_min Z         CFEAR k-strongest noise floor                     [60]
  --cfear_resolution M    CFEAR grid / association radius [m]               [3.0]
  --no_cfear              skip the CFEAR baselines (radar only anyway)
  --no_motion_compensation  do not compensate motion distortion
Classifier / evaluation:
  --folds K               k-fold CV over contiguous blocks of pairs         [5]
  --ridge L               L2 penalty on standardized slopes                 [0.001]
  --threshold T           t_h of Eq. 10                                     [0.5]
  --classifier_method M   method written to classifier.yaml                 [CorAl]
  --classifier_group G    magnitude it is trained on, e.g. "0.5 m" [first magnitude]
Output:
  --output DIR            classifier.yaml, samples.csv, report.md, roc.png  [coral_train_output]
  --no_csv                do not write samples.csv
  --help                  this text
)";

// The typed options of this tool, read whole (eval/tool_args.hpp): a value that is not such a
// number ("0.5x", "12.7" for a count, "1,,2") throws naming the option, and main() exits 2.
// std::stod / std::stoi read "0.5x" as 0.5 and "12.7" as 12.
struct NumberOptions {
  const ToolArgs& args;
  double number(const std::string& option, double fallback) const {
    double v = fallback;
    std::string err;
    if (!numberOption(args, option, fallback, &v, &err)) throw std::invalid_argument(err);
    return v;
  }
  int count(const std::string& option, int fallback) const {  // an integer >= 0
    int v = fallback;
    std::string err;
    if (!intOption(args, option, fallback, 0, 1000000000, &v, &err))
      throw std::invalid_argument(err);
    return v;
  }
  std::vector<double> numbers(const std::string& option,
                              const std::vector<double>& fallback) const {
    std::vector<double> v;
    std::string err;
    if (!numberListOption(args, option, fallback, &v, &err)) throw std::invalid_argument(err);
    return v;
  }
};

void progressBar(const char* what, std::size_t done, std::size_t total) {
  const int width = 40;
  const int fill = total ? static_cast<int>(width * done / total) : width;
  std::fprintf(stderr, "\r%-9s [%s%s] %zu/%zu", what, std::string(fill, '#').c_str(),
               std::string(width - fill, ' ').c_str(), done, total);
  if (done == total) std::fprintf(stderr, "\n");
}

struct Input {
  std::string oxford, bag;
};

// Scans + poses from an Oxford folder or a bag, then every sample of the protocol.
bool loadSet(const Input& in, const OxfordTrainingConfig& ocfg,
             const ros_eval::BagTrainingOptions& bcfg, double spacing,
             const std::vector<Perturbation>& perts, const FeatureConfig& fcfg, SampleSet* set,
             std::size_t* n_scans) {
  std::vector<TrainingScan> scans;
  Isometries poses;
  std::string err;
  const Progress bar = [](std::size_t d, std::size_t t) { progressBar("scans", d, t); };
  if (!in.oxford.empty()) {
    OxfordDataset ds;
    if (!ds.load(in.oxford, &err) ||
        !loadOxfordTrainingScans(ds, ocfg, bar, &scans, &poses, &err)) {
      std::cerr << "coral_train: " << err << "\n";
      return false;
    }
  } else {
    ros_eval::BagTrainingSummary sum;
    if (!ros_eval::loadBagTrainingScans(in.bag, bcfg, bar, &scans, &poses, &sum, &err)) {
      std::cerr << "\ncoral_train: " << err << "\n";
      return false;
    }
    std::cerr << "\n"
              << in.bag << ": " << scans.size() << " scans with a pose of " << sum.scan_messages
              << " (" << sum.no_pose << " without pose, " << sum.bad_message << " malformed"
              << (sum.first_error.empty() ? "" : "; first: " + sum.first_error) << ")\n";
  }
  *n_scans = scans.size();
  const std::vector<ScanPair> pairs = makePairs(poses, spacing);
  if (!buildSampleSet(
          scans, pairs, perts, fcfg,
          [](std::size_t d, std::size_t t) { progressBar("samples", d, t); }, set, &err)) {
    std::cerr << "coral_train: " << err << "\n";
    return false;
  }
  return true;
}

// --preset: the tolerance mode (ros_eval/verdict_training.hpp).
int verdictMode(std::map<std::string, std::string>& opt, const NumberOptions& num,
                const std::vector<std::string>& datasets,
                const std::vector<std::string>& sample_files, const std::string& command) {
  for (const char* k : {"--oxford", "--bag", "--test_oxford", "--test_bag", "--magnitudes"})
    if (opt.count(k)) {
      std::cerr << "coral_train: " << k << " belongs to the paper protocol, not to --preset\n";
      return 2;
    }
  ros_eval::VerdictTrainingOptions v;
  v.preset = opt["--preset"];
  v.datasets = datasets;
  v.sample_files = sample_files;
  v.command = command;
  try {
    if (opt.count("--output")) v.output_dir = opt["--output"];
    v.write_csv = !opt.count("--no_csv");
    v.threads = num.count("--threads", v.threads);
    v.max_scans = num.count("--max_scans", v.max_scans);
    v.folds = num.count("--folds", v.folds);
    v.relative_margin = num.number("--relative_margin", v.relative_margin);
    v.aligned_spread = num.number("--aligned_spread", v.aligned_spread);
    if (opt.count("--scan_topic")) v.bag_scan_topic = opt["--scan_topic"];
    if (opt.count("--odom_topic")) v.bag_odom_topic = opt["--odom_topic"];
    if (opt.count("--fixed_frame")) v.bag_fixed_frame = opt["--fixed_frame"];
    if (opt.count("--shard")) {
      const std::string& s = opt["--shard"];
      const std::size_t slash = s.find('/');
      if (slash == std::string::npos) throw std::invalid_argument("--shard needs I/N");
      ToolArgs parts;  // I and N, each read whole as a count
      parts.values["--shard index"] = {s.substr(0, slash)};
      parts.values["--shard count"] = {s.substr(slash + 1)};
      const NumberOptions shard{parts};
      v.shard_index = shard.count("--shard index", v.shard_index);
      v.shard_count = shard.count("--shard count", v.shard_count);
    }
  } catch (const std::exception& e) {
    std::cerr << "coral_train: bad option value: " << e.what() << "\n";
    return 2;
  }
  return ros_eval::runVerdictTraining(v, std::cerr);
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> flags = {"--no_cfear", "--no_motion_compensation", "--no_csv"};
  const std::vector<std::string> options = {"--oxford",
                                            "--bag",
                                            "--scan_topic",
                                            "--odom_topic",
                                            "--fixed_frame",
                                            "--test_oxford",
                                            "--test_bag",
                                            "--sensor",
                                            "--max_scans",
                                            "--spacing",
                                            "--magnitudes",
                                            "--rotations",
                                            "--combined_yaw",
                                            "--radius",
                                            "--k",
                                            "--z_min",
                                            "--window",
                                            "--min_range",
                                            "--cfear_z_min",
                                            "--cfear_resolution",
                                            "--folds",
                                            "--ridge",
                                            "--threshold",
                                            "--classifier_method",
                                            "--classifier_group",
                                            "--output",
                                            "--preset",
                                            "--dataset",
                                            "--samples",
                                            "--shard",
                                            "--threads",
                                            "--relative_margin",
                                            "--aligned_spread"};
  ToolArgs args;
  if (const auto exit = readCommandLine("coral_train", kUsage, argc, argv, options, flags, &args))
    return *exit;
  // The command as given, for the report (arguments with a space quoted).
  std::string command = "rosrun coral_introspection coral_train";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    command += " " + (a.find(' ') == std::string::npos ? a : "\"" + a + "\"");
  }
  // The code below reads options by name: the last value of each, "1" for a flag given.
  std::map<std::string, std::string> opt;
  for (const auto& [name, values] : args.values) opt[name] = values.back();
  for (const std::string& f : args.flags) opt[f] = "1";
  const std::vector<std::string> datasets = args.all("--dataset"),
                                 sample_files = args.all("--samples");
  const NumberOptions num{args};
  if (opt.count("--preset")) return verdictMode(opt, num, datasets, sample_files, command);
  if (opt.count("--oxford") == opt.count("--bag")) {
    std::cerr << "coral_train: give exactly one of --oxford DIR and --bag FILE\n" << kUsage;
    return 2;
  }
  auto get = [&](const char* k, const std::string& def) { return opt.count(k) ? opt[k] : def; };

  try {
    const Input train_in{get("--oxford", ""), get("--bag", "")};
    const Input test_in{get("--test_oxford", ""), get("--test_bag", "")};
    const bool tt = !test_in.oxford.empty() || !test_in.bag.empty();
    // Radar defaults for an Oxford folder or a bag whose scan topic carries polar images.
    const bool images =
        !train_in.bag.empty() &&
        ros_eval::bagTopicType(train_in.bag,
                               get("--scan_topic", ros_eval::BagTrainingOptions().scan_topic)) ==
            "sensor_msgs/Image";
    const std::string sensor =
        get("--sensor", train_in.oxford.empty() && !images ? "lidar3d" : "radar");
    if (sensor != "radar" && sensor != "lidar3d" && sensor != "lidar2d") {
      std::cerr << "coral_train: --sensor must be radar, lidar3d or lidar2d (got " << sensor
                << ")\n";
      return 2;
    }
    const bool radar = sensor == "radar";
    // Defaults per sensor: Sec. V-A (radar) and Sec. IV (lidar) of the paper.
    PerturbationConfig pcfg =
        radar ? PerturbationConfig::radarProtocol() : PerturbationConfig::lidarProtocol();
    pcfg.translations = num.numbers("--magnitudes", pcfg.translations);
    pcfg.rotations = num.numbers("--rotations", pcfg.rotations);
    pcfg.combined_yaw = num.number("--combined_yaw", pcfg.combined_yaw);
    FeatureConfig fcfg = radar ? FeatureConfig::radar() : FeatureConfig::lidar();
    if (sensor == "lidar2d") {
      fcfg.coral.dimension = fcfg.ndt.dimension = 2;
      fcfg.coral.radius = 0.5;
    }
    fcfg.coral.radius = num.number("--radius", fcfg.coral.radius);
    fcfg.ndt.voxel_size = 2.0 * fcfg.coral.radius;  // v = 2 r (Sec. IV-1 d)
    fcfg.cfear.resolution = num.number("--cfear_resolution", fcfg.cfear.resolution);
    fcfg.with_cfear = radar && !opt.count("--no_cfear");
    OxfordTrainingConfig ocfg;
    ocfg.rip.k = ocfg.cfear_k = num.count("--k", ocfg.rip.k);
    ocfg.rip.z_min = num.number("--z_min", ocfg.rip.z_min);
    ocfg.rip.window = num.count("--window", ocfg.rip.window);
    ocfg.rip.min_range = num.number("--min_range", ocfg.rip.min_range);
    ocfg.cfear_z_min = num.number("--cfear_z_min", ocfg.cfear_z_min);
    ocfg.with_cfear = fcfg.with_cfear;
    ocfg.motion_compensation = !opt.count("--no_motion_compensation");
    ocfg.max_scans = num.count("--max_scans", ocfg.max_scans);
    ros_eval::BagTrainingOptions bcfg;
    bcfg.scan_topic = get("--scan_topic", bcfg.scan_topic);
    bcfg.odom_topic = get("--odom_topic", bcfg.odom_topic);
    bcfg.fixed_frame = get("--fixed_frame", bcfg.fixed_frame);
    bcfg.node.rip = ocfg.rip;
    bcfg.node.online.coral = fcfg.coral;
    bcfg.motion_compensation = ocfg.motion_compensation;
    bcfg.with_cfear = ocfg.with_cfear;
    bcfg.cfear_k = ocfg.cfear_k;
    bcfg.cfear_z_min = ocfg.cfear_z_min;
    bcfg.max_scans = ocfg.max_scans;
    TrainingRunConfig rcfg;
    rcfg.output_dir = get("--output", rcfg.output_dir);
    rcfg.evaluation.folds = num.count("--folds", rcfg.evaluation.folds);
    rcfg.evaluation.regression.ridge = num.number("--ridge", rcfg.evaluation.regression.ridge);
    rcfg.evaluation.regression.threshold =
        num.number("--threshold", rcfg.evaluation.regression.threshold);
    rcfg.classifier_method = get("--classifier_method", rcfg.classifier_method);
    rcfg.classifier_group = get("--classifier_group", rcfg.classifier_group);
    rcfg.write_csv = !opt.count("--no_csv");
    for (const std::string& e :
         {pcfg.validate(), fcfg.validate(), ocfg.validate(),
          train_in.bag.empty() ? std::string() : bcfg.validate(), rcfg.validate()})
      if (!e.empty()) {
        std::cerr << "coral_train: invalid configuration: " << e << "\n";
        return 2;
      }
    const double spacing = num.number("--spacing", 0.0);
    const std::vector<Perturbation> perts = makePerturbations(pcfg);

    SampleSet train, test;
    std::size_t n_train = 0, n_test = 0;
    if (!loadSet(train_in, ocfg, bcfg, spacing, perts, fcfg, &train, &n_train)) return 1;
    if (tt && !loadSet(test_in, ocfg, bcfg, spacing, perts, fcfg, &test, &n_test)) return 1;

    auto name = [](const Input& in) { return in.oxford.empty() ? in.bag : in.oxford; };
    std::ostringstream d;
    d << "Data: " << name(train_in) << " (" << n_train << " scans, "
      << (train.samples.size() / (1 + perts.size())) << " pairs"
      << (spacing > 0 ? ", spacing >= " + std::to_string(spacing) + " m" : ", consecutive") << ")";
    if (tt) d << "; test: " << name(test_in) << " (" << n_test << " scans)";
    std::ostringstream st;
    st << "Settings: sensor " << sensor << "; CorAl " << fcfg.coral.dimension
       << "D r = " << fcfg.coral.radius << " m, E_reject = " << fcfg.coral.e_reject
       << ", epsilon = " << fcfg.coral.epsilon << "; NDT v = " << fcfg.ndt.voxel_size << " m";
    if (radar)
      st << "; RIP k = " << ocfg.rip.k << ", z_min = " << ocfg.rip.z_min
         << ", w = " << ocfg.rip.window << ", min range " << ocfg.rip.min_range
         << " m; CFEAR z_min = " << ocfg.cfear_z_min << ", r = " << fcfg.cfear.resolution
         << " m; motion compensation " << (ocfg.motion_compensation ? "on" : "off");
    st << "; logistic regression with balanced class weights, ridge "
       << rcfg.evaluation.regression.ridge << ", t_h = " << rcfg.evaluation.regression.threshold
       << ".";
    rcfg.report_header = {"# coral_train report",
                          "",
                          "Command (run from the repository root):",
                          "",
                          "```",
                          command,
                          "```",
                          "",
                          d.str(),
                          "",
                          st.str()};
    rcfg.provenance = {"command: " + command, d.str(), st.str()};
    if (radar)  // the published figures these rows correspond to, for an honest comparison
      rcfg.report_footer = {
          "",
          "## Paper reference (Table II, full Oxford sequences, consecutive scans)",
          "",
          "| Method | 0.3 m | 0.5 m | 0.7 m |",
          "|---|---|---|---|",
          "| CFEAR-P2P | 0.59/0.61 | 0.69/0.77 | 0.85/0.95 |",
          "| CFEAR-P2L | 0.66/0.77 | 0.89/0.95 | 0.97/0.99 |",
          "| CFEAR-P2D | 0.57/0.66 | 0.76/0.85 | 0.89/0.96 |",
          "| CorAl | 0.91/0.98 | 0.97/1.00 | 0.99/1.00 |",
          "",
          "The paper's figures rest on thousands of pairs from four Oxford sequences; the rows "
          "above rest on the pairs counted in the detailed table (one held-out fold holds "
          "about pairs / folds of them), so one misclassified sample moves a cell by several "
          "points. Compare orderings, not second decimals."};
    TrainingRunResult res;
    std::string err;
    if (!runTraining(train, tt ? &test : nullptr, rcfg, &res, &err)) {
      std::cerr << "coral_train: " << err << "\n";
      return 1;
    }
    std::cout << res.report << "\nWrote " << rcfg.output_dir
              << "/{classifier.yaml, report.md, roc.png" << (rcfg.write_csv ? ", samples.csv" : "")
              << "}\n";
  } catch (const std::exception& e) {  // NumberOptions on a malformed number
    std::cerr << "coral_train: bad option value: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
