// Held-out evaluation of alignment classifiers (paper Sec. III-F, IV, V-C, Table II):
// per method x error magnitude, logistic regression trained by k-fold cross-validation over
// contiguous blocks of pairs (never in-sample), or trained on one data set and tested on
// another.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "coral_introspection/coral/logistic_regression.hpp"

namespace coral_introspection {
namespace eval {

// A quality measure and the classifier inputs it provides (x1, x2, ...).
struct MethodSpec {
  std::string name;                        // e.g. "CorAl", "NDT", "CFEAR-P2L"
  std::vector<std::string> feature_names;  // e.g. {"H_joint", "H_sep"}
};

// One aligned or misaligned version of a scan pair.
struct Sample {
  int pair = 0;                           // pair index; every sample of a pair lands in one fold
  std::string dataset;                    // data set the pair comes from (may be empty)
  double stamp_a = 0.0, stamp_b = 0.0;    // [s]
  std::string offset = "aligned";         // perturbation name ("forward", "yaw+", ...)
  std::string group;                      // error-magnitude label; empty when aligned
  double dx = 0.0, dy = 0.0, dyaw = 0.0;  // induced offset in b's frame [m, m, rad]
  int label = 1;                          // 1 = aligned, 0 = misaligned
  // features[m] = inputs of methods[m]; NaN where the method gave no valid value.
  std::vector<std::vector<double>> features;
};

struct SampleSet {
  std::vector<MethodSpec> methods;
  std::vector<std::string> groups;  // error magnitudes, report order
  std::vector<Sample> samples;
};

struct EvaluationConfig {
  int folds = 5;                               // k of the contiguous k-fold cross-validation
  coral::LogisticRegressionConfig regression;  // balanced class weights by default
  std::string validate() const;                // empty when valid
};

// One cell of Table II: a method at one error magnitude, on held-out predictions.
struct EvaluationRow {
  std::string method, group;
  double accuracy = 0.0;        // balanced (each class half), threshold t_h
  double plain_accuracy = 0.0;  // fraction of samples right
  double auc = 0.0;
  int pairs = 0;                    // distinct pairs behind the numbers
  int aligned = 0, misaligned = 0;  // held-out samples with a valid feature vector
  int skipped = 0;                  // samples without a valid feature (method failed)
  int folds = 0;                    // folds actually evaluated (0 for train/test)
  std::vector<double> scores;       // held-out probabilities of "aligned" (for ROC)
  std::vector<int> labels;
};

// Samples usable for (method, group): aligned ones plus misaligned ones of the group
// (group empty = every misaligned sample), with finite features.
void selectSamples(const SampleSet& set, int method, const std::string& group,
                   std::vector<int>* indices, int* skipped);

// Fits method `method` on the samples with the given indices (finite features expected).
bool fitSamples(const SampleSet& set, int method, const std::vector<int>& indices,
                const coral::LogisticRegressionConfig& cfg, coral::LogisticModel* model,
                std::string* error);

// Fills pairs, class counts, accuracies (at `threshold`) and AUC of a row from its scores
// and labels; `indices` are the samples behind them (for the pair count).
void summarizeRow(const SampleSet& set, const std::vector<int>& indices, double threshold,
                  EvaluationRow* row);

// Fits method `method` on the samples of `group` (empty = all magnitudes).
bool fitMethod(const SampleSet& set, int method, const std::string& group,
               const coral::LogisticRegressionConfig& cfg, coral::LogisticModel* model,
               std::string* error);

// k-fold over contiguous blocks of pair indices; one row per method x group.
bool crossValidate(const SampleSet& set, const EvaluationConfig& cfg,
                   std::vector<EvaluationRow>* rows, std::string* error);

// Generalization test: fit on `train`, evaluate on `test` (same methods and groups).
bool trainTest(const SampleSet& train, const SampleSet& test, const EvaluationConfig& cfg,
               std::vector<EvaluationRow>* rows, std::string* error);

}  // namespace eval
}  // namespace coral_introspection
