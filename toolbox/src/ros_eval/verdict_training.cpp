#include "coral_introspection/ros_eval/verdict_training.hpp"

#include <sys/stat.h>
#include <algorithm>
#include <cstdio>
#include <iomanip>
#include <sstream>

#include "coral_introspection/eval/pair_datasets.hpp"
#include "coral_introspection/eval/sample_csv.hpp"
#include "coral_introspection/eval/training_report.hpp"
#include "coral_introspection/eval/verdict_report.hpp"
#include "coral_introspection/eval/verdict_samples.hpp"
#include "coral_introspection/ros_eval/bag_training_reader.hpp"
#include "coral_introspection/ros_eval/preset_file.hpp"

namespace coral_introspection {
namespace ros_eval {

namespace {

eval::Progress bar(const std::string& what, std::ostream& log) {
  return [what, &log](std::size_t done, std::size_t total) {
    if (done == total || done % std::max<std::size_t>(1, total / 20) == 0)
      log << "\r" << what << " " << done << "/" << total << (done == total ? "\n" : "")
          << std::flush;
  };
}

bool loadData(const eval::DatasetSpec& spec, const ros_adapters::NodeConfig& node,
              const VerdictTrainingOptions& o, std::ostream& log, eval::PairDataset* d,
              std::string* error) {
  if (spec.kind != "bag") {
    eval::DatasetOptions opt;
    opt.oxford.rip = node.rip;
    opt.oxford.with_cfear = false;
    opt.oxford.motion_compensation = node.online.deskew.enabled;
    opt.oxford.max_scans = opt.keyframes.max_scans = o.max_scans;
    return eval::loadPairDataset(spec, opt, bar(spec.name + " scans", log), d, error);
  }
  BagTrainingOptions b;
  b.scan_topic = o.bag_scan_topic;
  b.odom_topic = o.bag_odom_topic;
  b.fixed_frame = o.bag_fixed_frame;
  b.node = node;
  b.motion_compensation = node.online.deskew.enabled;
  b.with_cfear = false;
  b.max_scans = o.max_scans;
  coral::Isometries poses;
  BagTrainingSummary sum;
  *d = eval::PairDataset();
  d->name = spec.name;
  if (!loadBagTrainingScans(spec.path, b, bar(spec.name + " scans", log), &d->scans, &poses, &sum,
                            error))
    return false;
  d->pairs = eval::makePairs(poses, 0.0);
  d->summary = std::to_string(d->scans.size()) + " scans with a pose, " +
               std::to_string(d->pairs.size()) + " consecutive pairs";
  return true;
}

std::string coralSettings(const coral::CoralConfig& c) {
  std::ostringstream s;
  s << "CorAl " << c.dimension << "D, r = " << c.radius << " m"
    << (c.dynamic_radius
            ? " (dynamic " + std::to_string(c.r_min) + "-" + std::to_string(c.r_max) + ")"
            : "")
    << ", epsilon = " << c.epsilon << ", E_reject = " << c.e_reject << ", min neighbours "
    << c.min_neighbours << "/" << c.min_neighbours_other << ", min overlap " << c.min_overlap;
  return s.str();
}

}  // namespace

int runVerdictTraining(const VerdictTrainingOptions& o, std::ostream& log) {
  ros_adapters::NodeConfig node;
  coral::VerdictConfig verdict;
  std::string err;
  if (!loadPresetFile(o.preset, &node, &verdict, &err)) {
    log << "coral_train: " << err << "\n";
    return 2;
  }
  if (o.relative_margin >= 0.0) verdict.relative.margin = o.relative_margin;
  if (o.datasets.empty() == o.sample_files.empty()) {
    log << "coral_train: give data sets (--dataset) or sample files (--samples), not both\n";
    return 2;
  }
  eval::VerdictSampleConfig scfg;
  scfg.coral = node.online.coral;
  scfg.tolerance = verdict.tolerance;
  scfg.probe_queries = verdict.relative.probe_queries;
  scfg.aligned_spread = o.aligned_spread;
  scfg.threads = o.threads;
  scfg.shard_index = o.shard_index;
  scfg.shard_count = o.shard_count;
  if (const std::string e = scfg.validate(); !e.empty()) {
    log << "coral_train: " << e << "\n";
    return 2;
  }
  mkdir(o.output_dir.c_str(), 0755);  // may exist; writes below report failures

  eval::SampleSet set;
  std::vector<std::string> data_lines;
  for (const std::string& text : o.datasets) {
    eval::DatasetSpec spec;
    eval::PairDataset d;
    eval::SampleSet part;
    eval::CoralCost cost;
    if (!eval::parseDatasetSpec(text, &spec, &err) || !loadData(spec, node, o, log, &d, &err) ||
        !eval::buildVerdictSamples(spec.name, d.scans, d.pairs, scfg,
                                   bar(spec.name + " pairs", log), &part, &err, &cost) ||
        !eval::mergeSampleSets(&set, part, &err)) {
      log << "coral_train: " << err << "\n";
      return 1;
    }
    std::ostringstream c;
    c << "; " << cost.evaluations << " CorAl evaluations, " << std::setprecision(3)
      << 1e3 * cost.seconds / std::max<std::size_t>(1, cost.evaluations) << " ms each on average";
    data_lines.push_back("- " + spec.name + " (`" + spec.kind + ":" + spec.path +
                         "`): " + d.summary + c.str());
  }
  for (const std::string& path : o.sample_files) {
    eval::SampleSet part;
    if (!eval::readSamplesCsv(path, &part, &err) || !eval::mergeSampleSets(&set, part, &err)) {
      log << "coral_train: " << err << "\n";
      return 1;
    }
    data_lines.push_back("- samples from `" + path + "`");
  }
  if (o.shard_count > 1) {  // a shard only writes its samples
    char name[64];
    std::snprintf(name, sizeof(name), "/samples_shard%dof%d.csv", o.shard_index, o.shard_count);
    if (!eval::writeSamplesCsv(o.output_dir + name, set, &err)) {
      log << "coral_train: " << err << "\n";
      return 1;
    }
    log << "Wrote " << o.output_dir << name << " (" << set.samples.size() << " samples)\n";
    return 0;
  }

  eval::VerdictEvalConfig ecfg;
  ecfg.evaluation.folds = o.folds;
  ecfg.relative = verdict.relative;
  eval::VerdictEvaluation ev;
  if (!eval::evaluateVerdicts(set, ecfg, &ev, &err)) {
    log << "coral_train: " << err << "\n";
    return 1;
  }
  verdict.method = ev.best;
  verdict.classifier = ev.classifier.toClassifierConfig();
  std::ostringstream tol, choice;
  tol << "Tolerance: " << verdict.tolerance.translation << " m along x, y"
      << (node.online.coral.dimension == 3 ? ", z" : "") << "; " << verdict.tolerance.rotation_deg
      << " deg about yaw" << (node.online.coral.dimension == 3 ? ", roll, pitch" : "")
      << " (offsets applied in the later scan's sensor frame). " << coralSettings(node.online.coral)
      << " (from the preset).";
  choice << "Default method: **" << coral::verdictMethodName(ev.best)
         << "** (rule: highest mean leave-one-out balanced accuracy; within 0.005 the cheaper "
            "method wins: classifier, then relative). Deployed classifier fitted on every "
            "sample: beta0 = "
         << verdict.classifier.beta0 << ", beta1 = " << verdict.classifier.beta1
         << ", beta2 = " << verdict.classifier.beta2 << ".";
  std::vector<std::string> header = {"# Verdict at the tolerance: `" + o.preset + "`",
                                     "",
                                     "Generated by (from the repository root):",
                                     "",
                                     "```",
                                     o.command,
                                     "```",
                                     "",
                                     "Data:",
                                     ""};
  header.insert(header.end(), data_lines.begin(), data_lines.end());
  const int axes = node.online.coral.dimension == 2 ? 3 : 6;
  std::ostringstream cost;
  cost << "Cost per verdict: classifier 1 CorAl evaluation; relative and both 1 + 2 x " << axes
       << " = " << 1 + 2 * axes << " (the per-evaluation times above are from this machine, "
       << "measured while building the samples).";
  header.insert(header.end(), {"", tol.str(), "", cost.str(), "", choice.str()});
  header.insert(header.end(), o.notes.begin(), o.notes.end());
  const std::string report = eval::verdictMarkdown(set, ev, ecfg, header);
  std::vector<std::string> comments = {
      "Verdict settings written by coral_train for " + o.preset, "command: " + o.command,
      "tolerance and classifier/* trained and chosen on: " + std::to_string(ev.datasets.size()) +
          " evaluation data sets (see report.md)"};
  std::ostringstream row;  // | preset | data sets | tolerance | LODO accuracies | default |
  row << "| `" << o.preset << "` | " << ev.datasets.size() << ": ";
  for (std::size_t i = 0; i < ev.datasets.size(); ++i) row << (i ? ", " : "") << ev.datasets[i];
  row << " | " << verdict.tolerance.translation << " m, " << verdict.tolerance.rotation_deg
      << " deg |";
  for (double a : ev.lodo_accuracy) row << ' ' << std::fixed << std::setprecision(3) << a << " |";
  row << " **" << coral::verdictMethodName(ev.best) << "** |\n";
  if (!eval::writeTextFile(o.output_dir + "/report.md", report, &err) ||
      !eval::writeTextFile(o.output_dir + "/verdict.yaml", eval::verdictYaml(verdict, comments),
                           &err) ||
      !eval::writeVerdictRocPng(o.output_dir + "/roc.png", set, ev, &err) ||
      !eval::writeTextFile(o.output_dir + "/summary.md", row.str(), &err) ||
      (o.write_csv && !eval::writeSamplesCsv(o.output_dir + "/samples.csv", set, &err))) {
    log << "coral_train: " << err << "\n";
    return 1;
  }
  log << report << "\nWrote " << o.output_dir << "/{report.md, roc.png, verdict.yaml, summary.md"
      << (o.write_csv ? ", samples.csv}\n" : "}\n");
  return 0;
}

}  // namespace ros_eval
}  // namespace coral_introspection
