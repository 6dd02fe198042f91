// One training / evaluation run of coral_train, ROS-free so it is testable: evaluates every
// method (cross-validation or train/test), fits the deployable classifier and writes
// classifier.yaml, samples.csv, report.md and roc.png into an output folder.
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/eval/evaluation.hpp"

namespace coral_introspection {
namespace eval {

struct TrainingRunConfig {
  std::string output_dir = "coral_train_output";
  EvaluationConfig evaluation;              // 5-fold contiguous CV, balanced weights
  std::string classifier_method = "CorAl";  // method whose fit goes into classifier.yaml
  // Error magnitude the deployed classifier is trained to detect; empty = the first
  // (smallest) group, i.e. the tightest boundary (0.3 m for the radar protocol).
  std::string classifier_group;
  bool write_csv = true;
  std::vector<std::string> report_header;  // markdown lines put first (command, data)
  std::vector<std::string> provenance;     // plain lines for the YAML comments
  std::vector<std::string> report_footer;  // markdown lines put last (e.g. paper figures)
  std::string validate() const;            // empty when valid
};

struct TrainingRunResult {
  std::vector<EvaluationRow> rows;
  coral::LogisticModel classifier;  // fitted on every sample of classifier_group
  std::string classifier_group;     // the group actually used
  std::string report;               // report.md text
};

// Fraction of pairs where CorAl's Q = H_joint - H_sep is lower when aligned than for
// each misalignment of `group`: a classifier-free check of the measure (count of
// comparisons won, count of comparisons with both values valid).
void qualityOrdering(const SampleSet& set, const std::string& group, int* wins, int* total);

// test_set == nullptr: k-fold CV on `set`; otherwise train on `set`, test on *test_set.
bool runTraining(const SampleSet& set, const SampleSet* test_set, const TrainingRunConfig& cfg,
                 TrainingRunResult* result, std::string* error);

}  // namespace eval
}  // namespace coral_introspection
