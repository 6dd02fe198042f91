#include "coral_introspection/eval/verdict_report.hpp"

#include <array>
#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>

#include "coral_introspection/coral/metrics.hpp"
#include "coral_introspection/eval/training_report.hpp"

namespace coral_introspection {
namespace eval {

namespace {

std::string f2(double v) {
  if (!std::isfinite(v)) return "n/a";
  std::ostringstream s;
  s << std::fixed << std::setprecision(2) << v;
  return s.str();
}

std::string cell(const VerdictScenario& sc, int method, const std::string& group = "all") {
  for (const EvaluationRow& r : sc.rows)
    if (r.method == coral::verdictMethodName(kVerdictMethods[method]) && r.group == group)
      return f2(r.accuracy) + " / " + f2(r.auc);
  return "n/a";
}

const char* kMethodHeader = " classifier | relative | both |";

// One table: a row per scenario of `kind`, cells accuracy / AUC of each method.
void scenarioTable(std::ostringstream& s, const VerdictEvaluation& e, const std::string& kind,
                   const std::string& first_column, bool with_train) {
  s << "| " << first_column << " |" << kMethodHeader << "\n|---|---|---|---|\n";
  for (const VerdictScenario& sc : e.scenarios)
    if (sc.kind == kind)
      s << "| " << (with_train ? sc.train + " -> " : "") << sc.test << " | " << cell(sc, 0) << " | "
        << cell(sc, 1) << " | " << cell(sc, 2) << " |\n";
}

// Per offset: share judged misaligned (aligned row: share judged aligned) in `kind`.
void directionTable(std::ostringstream& s, const SampleSet& set, const VerdictEvaluation& e,
                    const std::string& kind) {
  std::vector<std::string> names;
  std::map<std::string, std::array<std::array<int, 2>, 3>> count;  // name -> method -> {ok, n}
  for (const VerdictScenario& sc : e.scenarios) {
    if (sc.kind != kind) continue;
    for (std::size_t k = 0; k < sc.samples.size(); ++k) {
      const Sample& x = set.samples[sc.samples[k]];
      if (!count.count(x.offset)) names.push_back(x.offset);
      auto& c = count[x.offset];
      for (int m = 0; m < 3; ++m) {
        ++c[m][1];  // a sample without a verdict counts as wrong: the user gets no answer
        if (std::isfinite(sc.p[m][k]) && (sc.p[m][k] >= 0.5) == (x.label == 1)) ++c[m][0];
      }
    }
  }
  s << "| Offset (b's frame) | samples |" << kMethodHeader << "\n|---|---|---|---|---|\n";
  for (const std::string& n : names) {
    const auto& c = count[n];
    s << "| " << n << " | " << c[0][1];
    for (int m = 0; m < 3; ++m) s << " | " << f2(static_cast<double>(c[m][0]) / c[m][1]);
    s << " |\n";
  }
}

// Relative check: correction hint right (points back to the truth) and flat axes.
void relativeDiagnostics(std::ostringstream& s, const SampleSet& set,
                         const VerdictEvalConfig& cfg) {
  const std::vector<coral::RelativeCheckResult> rel = relativeResults(set, cfg.relative);
  int detected = 0, hint_ok = 0, aligned = 0;
  std::map<std::string, int> flat;
  for (std::size_t i = 0; i < set.samples.size(); ++i) {
    const Sample& x = set.samples[i];
    const coral::RelativeCheckResult& r = rel[i];
    if (!r.valid) continue;
    if (x.label == 1) {
      ++aligned;
      for (coral::Axis a : r.flat_axes) ++flat[coral::axisName(a)];
    } else if (r.misaligned) {
      ++detected;
      std::string back = x.offset;  // the step back to the truth: same axis, other sign
      back.back() = back.back() == '+' ? '-' : '+';
      if (r.hint.name == back) ++hint_ok;
    }
  }
  s << "- Correction hint: of " << detected << " misaligned samples the relative check flagged, "
    << hint_ok << " (" << f2(detected ? 100.0 * hint_ok / detected : NAN)
    << " %) name the step back to the ground truth as the best neighbour.\n"
    << "- Flat (unobservable) axes at ground truth, share of " << aligned << " aligned samples:";
  for (const auto& kv : flat)
    s << ' ' << kv.first << ' ' << f2(100.0 * kv.second / aligned) << " %;";
  if (flat.empty()) s << " none";
  s << "\n";
}

// Balanced accuracy of the relative check for other margins, per left-out data set: shows
// how much the fixed default depends on its value.
void marginTable(std::ostringstream& s, const SampleSet& set, const VerdictEvaluation& e,
                 const VerdictEvalConfig& cfg) {
  const double margins[] = {0.0, 0.1, 0.2, 0.3, 0.5};
  s << "\n| Data set | margin 0 | 0.1 | 0.2 | 0.3 | 0.5 |\n|---|---|---|---|---|---|\n";
  std::vector<std::vector<coral::RelativeCheckResult>> rel;
  for (double m : margins) {
    coral::RelativeCheckConfig c = cfg.relative;
    c.margin = m;
    rel.push_back(relativeResults(set, c));
  }
  for (const VerdictScenario& sc : e.scenarios) {
    if (sc.kind != "lodo") continue;
    s << "| " << sc.test;
    for (const auto& r : rel) {
      std::vector<double> scores;
      std::vector<int> labels;
      for (int i : sc.samples) {
        scores.push_back(r[i].valid && !r[i].misaligned ? 1.0 : 0.0);
        labels.push_back(set.samples[i].label);
      }
      s << " | " << f2(coral::accuracy(scores, labels, 0.5, true));
    }
    s << " |\n";
  }
}

// Q at ground truth below Q with each offset, per data set (no classifier involved).
void qOrdering(std::ostringstream& s, const SampleSet& set) {
  std::map<std::pair<std::string, int>, double> q_gt;
  for (const Sample& x : set.samples)
    if (x.label == 1) q_gt[{x.dataset, x.pair}] = x.features[1][0];
  std::map<std::string, std::array<int, 2>> wins;
  for (const Sample& x : set.samples) {
    if (x.label == 1) continue;
    const auto it = q_gt.find({x.dataset, x.pair});
    if (it == q_gt.end() || !std::isfinite(it->second) || !std::isfinite(x.features[1][0]))
      continue;
    auto& w = wins[x.dataset];
    ++w[1];
    if (it->second < x.features[1][0]) ++w[0];
  }
  for (const auto& kv : wins)
    s << "- " << kv.first << ": " << kv.second[0] << "/" << kv.second[1] << "\n";
}

}  // namespace

std::string verdictMarkdown(const SampleSet& set, const VerdictEvaluation& e,
                            const VerdictEvalConfig& cfg, const std::vector<std::string>& header) {
  std::ostringstream s;
  for (const std::string& h : header) s << h << '\n';
  s << "\nCells: held-out balanced accuracy / AUC at the tolerance (aligned vs every induced "
       "offset of one tolerance), threshold 0.5. A sample without a verdict (CorAl invalid) is "
       "left out of these cells and counted in the detail table.\n";
  s << "\n## Leave one data set out (trained without the tested data set)\n\n";
  scenarioTable(s, e, "lodo", "Tested on (trained on the rest)", false);
  s << "| **mean** | " << f2(e.lodo_accuracy[0]) << " | " << f2(e.lodo_accuracy[1]) << " | "
    << f2(e.lodo_accuracy[2]) << " |\n";
  s << "\nPer offset (same held-out predictions; aligned row: share judged aligned, others: "
       "share judged misaligned; no verdict counts as wrong):\n\n";
  directionTable(s, set, e, "lodo");
  s << "\n## In data set (contiguous k-fold cross-validation over pairs)\n\n";
  scenarioTable(s, e, "cv", "Data set", false);
  s << "\n(A data set with fewer than two pairs has no row here.)\n";
  if (e.datasets.size() > 2) {
    s << "\n## Cross data set (train -> test)\n\n";
    scenarioTable(s, e, "cross", "Train -> test", true);
  }
  s << "\n## Relative check\n\nMargin " << cfg.relative.margin << ", flat ratio "
    << cfg.relative.flat_ratio
    << " (preset values, not fitted to these samples; a no-verdict counts as misaligned in "
       "the margin table below).\n\n";
  relativeDiagnostics(s, set, cfg);
  marginTable(s, set, e, cfg);
  s << "\n## CorAl Q ordering (no classifier)\n\nQ at ground truth below Q with the offset:\n\n";
  qOrdering(s, set);
  s << "\n## Detail\n\n| Scenario | Method | Errors | Acc. (balanced) | Acc. (plain) | AUC | "
       "Pairs | Aligned | Misaligned | No verdict |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const VerdictScenario& sc : e.scenarios)
    for (const EvaluationRow& r : sc.rows)
      s << "| " << sc.kind << ": " << sc.train << " -> " << sc.test << " | " << r.method << " | "
        << r.group << " | " << f2(r.accuracy) << " | " << f2(r.plain_accuracy) << " | " << f2(r.auc)
        << " | " << r.pairs << " | " << r.aligned << " | " << r.misaligned << " | " << r.skipped
        << " |\n";
  return s.str();
}

bool writeVerdictRocPng(const std::string& path, const SampleSet& set, const VerdictEvaluation& e,
                        std::string* error) {
  std::vector<EvaluationRow> rows;
  std::vector<std::string> panels;
  const std::map<std::string, std::string> title = {{"cv", "at tolerance, CV in data set"},
                                                    {"cross", "at tolerance, cross data set"},
                                                    {"lodo", "at tolerance, left-out data set"}};
  for (const char* kind : {"cv", "cross", "lodo"}) {
    EvaluationRow pooled[3];
    for (const VerdictScenario& sc : e.scenarios) {
      if (sc.kind != kind) continue;
      for (int m = 0; m < 3; ++m)
        for (std::size_t k = 0; k < sc.samples.size(); ++k)
          if (std::isfinite(sc.p[m][k])) {
            pooled[m].scores.push_back(sc.p[m][k]);
            pooled[m].labels.push_back(set.samples[sc.samples[k]].label);
          }
    }
    if (pooled[0].scores.empty() && pooled[1].scores.empty()) continue;
    panels.push_back(title.at(kind));
    for (int m = 0; m < 3; ++m) {
      pooled[m].method = coral::verdictMethodName(kVerdictMethods[m]);
      pooled[m].group = panels.back();
      summarizeRow(set, {}, 0.5, &pooled[m]);
      rows.push_back(pooled[m]);
    }
  }
  return writeRocPng(path, rows, panels, error);
}

std::string verdictYaml(const coral::VerdictConfig& v, const std::vector<std::string>& comments) {
  std::ostringstream s;
  for (const std::string& c : comments) s << "# " << c << '\n';
  s << std::setprecision(12) << "tolerance:\n  translation: " << v.tolerance.translation
    << "\n  rotation_deg: " << v.tolerance.rotation_deg
    << "\nclassifier:\n  method: " << coral::verdictMethodName(v.method)
    << "\n  beta0: " << v.classifier.beta0 << "\n  beta1: " << v.classifier.beta1
    << "\n  beta2: " << v.classifier.beta2 << "\n  threshold: " << v.classifier.threshold
    << "\n  relative_margin: " << v.relative.margin << "\n  flat_ratio: " << v.relative.flat_ratio
    << '\n';
  return s.str();
}

}  // namespace eval
}  // namespace coral_introspection
