#include "coral_introspection/eval/evaluation.hpp"

#include "coral_introspection/coral/validation.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "coral_introspection/coral/metrics.hpp"

namespace coral_introspection {
namespace eval {

std::string EvaluationConfig::validate() const {
  return coral::Problems()
      .require(folds >= 2, "folds", ">= 2", folds)
      .nested("regression", regression.validate())
      .str();
}

void selectSamples(const SampleSet& set, int method, const std::string& group,
                   std::vector<int>* indices, int* skipped) {
  indices->clear();
  *skipped = 0;
  for (std::size_t i = 0; i < set.samples.size(); ++i) {
    const Sample& s = set.samples[i];
    if (s.label == 0 && !group.empty() && s.group != group) continue;
    const std::vector<double>& f = s.features.at(method);
    if (std::all_of(f.begin(), f.end(), [](double v) { return std::isfinite(v); }))
      indices->push_back(static_cast<int>(i));
    else
      ++*skipped;
  }
}

bool fitSamples(const SampleSet& set, int method, const std::vector<int>& idx,
                const coral::LogisticRegressionConfig& cfg, coral::LogisticModel* model,
                std::string* error) {
  const int d = static_cast<int>(set.methods.at(method).feature_names.size());
  Eigen::MatrixXd X(idx.size(), d);
  std::vector<int> y;
  for (std::size_t r = 0; r < idx.size(); ++r) {
    const Sample& s = set.samples[idx[r]];
    for (int j = 0; j < d; ++j) X(r, j) = s.features[method][j];
    y.push_back(s.label);
  }
  return coral::fitLogisticRegression(X, y, {}, cfg, model, error);
}

namespace {

double predict(const coral::LogisticModel& m, const Sample& s, int method) {
  const std::vector<double>& f = s.features[method];
  return m.probability(Eigen::Map<const Eigen::VectorXd>(f.data(), f.size()));
}

}  // namespace

void summarizeRow(const SampleSet& set, const std::vector<int>& idx, double threshold,
                  EvaluationRow* row) {
  std::set<int> pairs;
  for (int i : idx) pairs.insert(set.samples[i].pair);
  row->pairs = static_cast<int>(pairs.size());
  row->aligned = static_cast<int>(std::count(row->labels.begin(), row->labels.end(), 1));
  row->misaligned = static_cast<int>(row->labels.size()) - row->aligned;
  row->accuracy = coral::accuracy(row->scores, row->labels, threshold, true);
  row->plain_accuracy = coral::accuracy(row->scores, row->labels, threshold, false);
  row->auc = coral::auc(row->scores, row->labels);
}

bool fitMethod(const SampleSet& set, int method, const std::string& group,
               const coral::LogisticRegressionConfig& cfg, coral::LogisticModel* model,
               std::string* error) {
  std::vector<int> idx;
  int skipped = 0;
  selectSamples(set, method, group, &idx, &skipped);
  return fitSamples(set, method, idx, cfg, model, error);
}

bool crossValidate(const SampleSet& set, const EvaluationConfig& cfg,
                   std::vector<EvaluationRow>* rows, std::string* error) {
  if (const std::string e = cfg.validate(); !e.empty()) {
    if (error) *error = e;
    return false;
  }
  rows->clear();
  for (std::size_t m = 0; m < set.methods.size(); ++m)
    for (const std::string& g : set.groups) {
      EvaluationRow row;
      row.method = set.methods[m].name;
      row.group = g;
      std::vector<int> idx;
      selectSamples(set, static_cast<int>(m), g, &idx, &row.skipped);
      // Folds are contiguous blocks of the sorted pair indices, so neighbouring (and
      // thus similar) scans are never split between training and test.
      std::vector<int> pair_ids;
      for (int i : idx) pair_ids.push_back(set.samples[i].pair);
      std::sort(pair_ids.begin(), pair_ids.end());
      pair_ids.erase(std::unique(pair_ids.begin(), pair_ids.end()), pair_ids.end());
      const int np = static_cast<int>(pair_ids.size());
      const int k = std::min(cfg.folds, np);
      std::vector<int> scored;  // samples that were actually held out and predicted
      for (int f = 0; f < k; ++f) {
        const int lo = pair_ids[f * np / k], hi = pair_ids[(f + 1) * np / k - 1];
        std::vector<int> train, test;
        for (int i : idx) {
          const int p = set.samples[i].pair;
          (p >= lo && p <= hi ? test : train).push_back(i);
        }
        coral::LogisticModel model;
        std::string err;
        if (test.empty() ||
            !fitSamples(set, static_cast<int>(m), train, cfg.regression, &model, &err))
          continue;  // e.g. one class only in the training folds: this fold is not scored
        for (int i : test) {
          row.scores.push_back(predict(model, set.samples[i], static_cast<int>(m)));
          row.labels.push_back(set.samples[i].label);
          scored.push_back(i);
        }
        ++row.folds;
      }
      summarizeRow(set, scored, cfg.regression.threshold, &row);
      rows->push_back(row);
    }
  return true;
}

bool trainTest(const SampleSet& train, const SampleSet& test, const EvaluationConfig& cfg,
               std::vector<EvaluationRow>* rows, std::string* error) {
  if (const std::string e = cfg.validate(); !e.empty()) {
    if (error) *error = e;
    return false;
  }
  if (train.methods.size() != test.methods.size()) {
    if (error) *error = "train and test sets have different methods";
    return false;
  }
  rows->clear();
  for (std::size_t m = 0; m < test.methods.size(); ++m)
    for (const std::string& g : test.groups) {
      EvaluationRow row;
      row.method = test.methods[m].name;
      row.group = g;
      coral::LogisticModel model;
      std::string err;
      std::vector<int> idx;
      selectSamples(test, static_cast<int>(m), g, &idx, &row.skipped);
      if (fitMethod(train, static_cast<int>(m), g, cfg.regression, &model, &err))
        for (int i : idx) {
          row.scores.push_back(predict(model, test.samples[i], static_cast<int>(m)));
          row.labels.push_back(test.samples[i].label);
        }
      summarizeRow(test, row.scores.empty() ? std::vector<int>{} : idx, cfg.regression.threshold,
                   &row);
      rows->push_back(row);
    }
  return true;
}

}  // namespace eval
}  // namespace coral_introspection
