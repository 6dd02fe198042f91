// coral_train's tolerance mode: train and evaluate a preset's verdict on real data sets.
//  1. read the preset (CorAl, RIP, tolerance, verdict settings: preset_file.hpp);
//  2. per data set ("[name=]kind:path", pair_datasets.hpp, or bag:FILE), build verdict
//     samples on every core (verdict_samples.hpp), or read them from sample files;
//  3. with --shard i/n: write that shard's samples and stop (a job array runs the shards,
//     one more run fits from all their files);
//  4. otherwise evaluate (in data set, cross data set, leave one out) and write report.md,
//     roc.png, verdict.yaml (the preset's tolerance + classifier sections), samples.csv and
//     summary.md (one table row for an overview of several presets).
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace coral_introspection {
namespace ros_eval {

struct VerdictTrainingOptions {
  std::string preset;                     // config/*.yaml
  std::vector<std::string> datasets;      // "[name=]kind:path"
  std::vector<std::string> sample_files;  // samples.csv files to fit from (instead of data)
  std::string output_dir = "coral_train_output";
  int threads = 0;  // 0 = every core
  int shard_index = 0, shard_count = 1;
  int max_scans = 0;            // per data set; 0 = all
  int folds = 5;                // in-data-set cross-validation
  double relative_margin = -1;  // < 0: the preset's
  double aligned_spread = 0.0;  // eval::VerdictSampleConfig::aligned_spread [tolerances]
  std::string bag_scan_topic = "/scan", bag_odom_topic, bag_fixed_frame = "odom";
  bool write_csv = true;           // samples.csv beside the report
  std::string command;             // quoted in the report
  std::vector<std::string> notes;  // extra markdown lines for the report header
};

// Returns a process exit code (0 ok, 1 failure, 2 bad options); messages go to `log`.
int runVerdictTraining(const VerdictTrainingOptions& options, std::ostream& log);

}  // namespace ros_eval
}  // namespace coral_introspection
