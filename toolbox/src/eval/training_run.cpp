#include "coral_introspection/eval/training_run.hpp"

#include <sys/stat.h>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>

#include "coral_introspection/eval/training_report.hpp"

namespace coral_introspection {
namespace eval {

std::string TrainingRunConfig::validate() const {
  if (output_dir.empty()) return "output_dir must not be empty";
  if (classifier_method.empty()) return "classifier_method must not be empty";
  return evaluation.validate();
}

void qualityOrdering(const SampleSet& set, const std::string& group, int* wins, int* total) {
  *wins = *total = 0;
  int coral = -1;
  for (std::size_t m = 0; m < set.methods.size(); ++m)
    if (set.methods[m].name == "CorAl") coral = static_cast<int>(m);
  if (coral < 0) return;
  std::map<int, double> q_aligned;  // pair -> Q at ground truth (Eq. 5)
  for (const Sample& s : set.samples)
    if (s.label == 1) q_aligned[s.pair] = s.features[coral][0] - s.features[coral][1];
  for (const Sample& s : set.samples) {
    if (s.label == 1 || s.group != group || !q_aligned.count(s.pair)) continue;
    const double qa = q_aligned[s.pair], qm = s.features[coral][0] - s.features[coral][1];
    if (!std::isfinite(qa) || !std::isfinite(qm)) continue;
    ++*total;
    if (qa < qm) ++*wins;
  }
}

bool runTraining(const SampleSet& set, const SampleSet* test_set, const TrainingRunConfig& cfg,
                 TrainingRunResult* res, std::string* error) {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (const std::string e = cfg.validate(); !e.empty()) return fail(e);
  if (set.groups.empty()) return fail("no error magnitudes (no misaligned samples)");
  int method = -1;
  for (std::size_t m = 0; m < set.methods.size(); ++m)
    if (set.methods[m].name == cfg.classifier_method) method = static_cast<int>(m);
  if (method < 0) return fail("unknown classifier_method '" + cfg.classifier_method + "'");
  if (set.methods[method].feature_names.size() > 2)
    return fail("classifier_method must have 1 or 2 inputs (the nodelet uses beta0..beta2)");
  res->classifier_group = cfg.classifier_group.empty() ? set.groups.front() : cfg.classifier_group;
  if (std::find(set.groups.begin(), set.groups.end(), res->classifier_group) == set.groups.end())
    return fail("unknown classifier_group '" + res->classifier_group + "'");
  mkdir(cfg.output_dir.c_str(), 0755);  // may exist already; writes below report failures

  std::string err;
  const bool ok = test_set ? trainTest(set, *test_set, cfg.evaluation, &res->rows, &err)
                           : crossValidate(set, cfg.evaluation, &res->rows, &err);
  if (!ok) return fail(err);
  // The deployable classifier: every sample of the chosen magnitude (evaluation above is
  // held-out; this fit is not evaluated in-sample anywhere).
  if (!fitMethod(set, method, res->classifier_group, cfg.evaluation.regression, &res->classifier,
                 &err))
    return fail("classifier fit: " + err);
  const coral::ClassifierConfig cc = res->classifier.toClassifierConfig();

  std::ostringstream prov;
  int pairs = 0;
  for (const Sample& s : set.samples) pairs = std::max(pairs, s.pair + 1);
  std::vector<std::string> comments = {
      "CorAl alignment classifier written by coral_train (paper Sec. III-F, Eq. 9-10).",
      "p = 1 / (1 + exp(-(beta0 + beta1 * x1 + beta2 * x2))), aligned iff p >= threshold;",
      "inputs of method " + cfg.classifier_method + ":"};
  for (std::size_t j = 0; j < set.methods[method].feature_names.size(); ++j)
    comments.back() += std::string(j ? "," : "") + " x" + std::to_string(j + 1) + " = " +
                       set.methods[method].feature_names[j];
  prov << "trained on " << pairs << " pairs: aligned vs misaligned by " << res->classifier_group
       << ", class weights " << (cfg.evaluation.regression.balanced ? "balanced" : "uniform")
       << ", ridge " << cfg.evaluation.regression.ridge;
  comments.push_back(prov.str());
  for (const std::string& h : cfg.provenance) comments.push_back(h);
  comments.push_back("Load into the nodelet's private namespace: <rosparam file=\"...\"/>");
  if (!writeClassifierYaml(cfg.output_dir + "/classifier.yaml", cc, comments, &err))
    return fail(err);
  if (cfg.write_csv && !writeSamplesCsv(cfg.output_dir + "/samples.csv", set, &err))
    return fail(err);
  const SampleSet& eval_set = test_set ? *test_set : set;
  if (!writeRocPng(cfg.output_dir + "/roc.png", res->rows, eval_set.groups, &err)) return fail(err);

  std::ostringstream r;
  for (const std::string& h : cfg.report_header) r << h << '\n';
  r << "\n## Held-out classification ("
    << (test_set ? "trained on the training set, tested on the test set"
                 : std::to_string(cfg.evaluation.folds) +
                       "-fold cross-validation over contiguous blocks of pairs")
    << ")\n\n"
    << markdownTables(res->rows, eval_set.groups);
  r << "\n## CorAl Q ordering (no classifier)\n\nQ = H_joint - H_sep at ground truth lower than "
       "with "
       "the offset, per misaligned sample:\n\n";
  for (const std::string& g : eval_set.groups) {
    int w = 0, t = 0;
    qualityOrdering(eval_set, g, &w, &t);
    r << "- " << g << ": " << w << "/" << t << '\n';
  }
  r << "\n## Deployed classifier (`classifier.yaml`)\n\n"
    << cfg.classifier_method << " fitted on all " << pairs << " pairs, aligned vs "
    << res->classifier_group << ": beta0 = " << std::setprecision(6) << cc.beta0
    << ", beta1 = " << cc.beta1 << ", beta2 = " << cc.beta2 << ", threshold = " << cc.threshold
    << (res->classifier.converged ? "" : " (NOT converged)") << ".\n";
  for (const std::string& f : cfg.report_footer) r << f << '\n';
  res->report = r.str();
  return writeTextFile(cfg.output_dir + "/report.md", res->report, error);
}

}  // namespace eval
}  // namespace coral_introspection
