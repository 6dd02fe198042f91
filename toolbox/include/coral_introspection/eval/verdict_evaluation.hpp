// Held-out evaluation of the three verdict methods at the tolerance (verdict.hpp) on a set
// of verdict samples (verdict_samples.hpp) from one or more data sets of one sensor class:
//  - in-data-set: k-fold cross-validation over contiguous blocks of pairs;
//  - cross-data-set: train on A, test on B for every ordered pair of data sets;
//  - leave-one-data-set-out (LODO): train on all others, test on the one left out.
// A sensor class with a single data set is split into its first and second half of pairs
// (contiguous, so mostly different places) which then act as the two data sets.
// The classifier is trained (logistic regression on H_joint, H_sep, Eq. 9); the relative
// check has no trained parameter, its margin is fixed in advance; "both" combines the
// held-out classifier with the relative check.
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/coral/verdict.hpp"
#include "coral_introspection/eval/evaluation.hpp"

namespace coral_introspection {
namespace eval {

struct VerdictEvalConfig {
  EvaluationConfig evaluation;          // folds, logistic regression (balanced, ridge, t_h)
  coral::RelativeCheckConfig relative;  // margin and flat ratio of the relative check
  std::string validate() const;         // empty when valid
};

// One train/test arrangement and its held-out opinions per test sample.
struct VerdictScenario {
  std::string kind;          // "cv", "cross", "lodo"
  std::string train;         // label of the training data ("folds of X" for cv)
  std::string test;          // label of the test data
  std::vector<int> samples;  // test sample indices
  // Held-out probability of "aligned" per test sample and method (NaN: no verdict).
  std::vector<double> p[3];
  std::vector<EvaluationRow> rows;  // method x group ("all", "translation", "rotation")
};

struct VerdictEvaluation {
  std::vector<std::string> datasets;  // evaluation data sets (halves for a single one)
  std::vector<VerdictScenario> scenarios;
  coral::LogisticModel classifier;      // fitted on every sample (the deployable one)
  double lodo_accuracy[3] = {0, 0, 0};  // mean balanced accuracy over LODO scenarios
  coral::VerdictMethod best = coral::VerdictMethod::kClassifier;  // highest LODO accuracy
};

// Method order of the arrays above: classifier, relative, both.
extern const coral::VerdictMethod kVerdictMethods[3];

// Relative-check results of every sample from its stored Q values.
std::vector<coral::RelativeCheckResult> relativeResults(const SampleSet& set,
                                                        const coral::RelativeCheckConfig& cfg);

// Runs every scenario and fits the deployable classifier. `set` holds "CorAl" and
// "Relative" methods (verdictMethods()). False with *error on a bad config or set.
bool evaluateVerdicts(const SampleSet& set, const VerdictEvalConfig& cfg, VerdictEvaluation* out,
                      std::string* error);

}  // namespace eval
}  // namespace coral_introspection
