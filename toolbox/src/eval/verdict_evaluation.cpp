#include "coral_introspection/eval/verdict_evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "coral_introspection/coral/validation.hpp"
#include "coral_introspection/eval/verdict_samples.hpp"

namespace coral_introspection {
namespace eval {

const coral::VerdictMethod kVerdictMethods[3] = {coral::VerdictMethod::kClassifier,
                                                 coral::VerdictMethod::kRelative,
                                                 coral::VerdictMethod::kBoth};

std::string VerdictEvalConfig::validate() const {
  return coral::Problems()
      .nested("evaluation", evaluation.validate())
      .nested("relative", relative.validate())
      .str();
}

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Part {
  std::string name;
  std::vector<int> samples;
};

// Data sets in order of first appearance; a single one is split into halves of its pairs.
std::vector<Part> dataParts(const SampleSet& set) {
  std::vector<Part> parts;
  for (std::size_t i = 0; i < set.samples.size(); ++i) {
    const std::string& d = set.samples[i].dataset;
    auto it = std::find_if(parts.begin(), parts.end(), [&](const Part& p) { return p.name == d; });
    if (it == parts.end()) it = parts.insert(parts.end(), Part{d, {}});
    it->samples.push_back(static_cast<int>(i));
  }
  if (parts.size() != 1) return parts;
  std::vector<int> pairs;
  for (int i : parts[0].samples) pairs.push_back(set.samples[i].pair);
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  if (pairs.size() < 2) return parts;
  const int split = pairs[pairs.size() / 2];  // first pair of the second half
  Part first{parts[0].name + " (first half)", {}}, second{parts[0].name + " (second half)", {}};
  for (int i : parts[0].samples)
    (set.samples[i].pair < split ? first : second).samples.push_back(i);
  return {first, second};
}

bool finiteCoral(const Sample& s) {
  return std::isfinite(s.features[0][0]) && std::isfinite(s.features[0][1]);
}

// Classifier probabilities for `test` from a fit on `train` (NaN where untestable).
void classifierOpinions(const SampleSet& set, const std::vector<int>& train,
                        const std::vector<int>& test, const coral::LogisticRegressionConfig& cfg,
                        std::vector<double>* p) {
  std::vector<int> fit_idx;
  for (int i : train)
    if (finiteCoral(set.samples[i])) fit_idx.push_back(i);
  coral::LogisticModel model;
  std::string err;
  const bool ok = fitSamples(set, 0, fit_idx, cfg, &model, &err);
  for (int i : test)
    p->push_back(ok && finiteCoral(set.samples[i])
                     ? model.probability(Eigen::Vector2d(set.samples[i].features[0][0],
                                                         set.samples[i].features[0][1]))
                     : kNaN);
}

// Fills p[1], p[2] from the classifier's p[0] and the relative results; then the rows.
void finishScenario(const SampleSet& set, const std::vector<coral::RelativeCheckResult>& rel,
                    const coral::RelativeCheckConfig& rcfg, double threshold, VerdictScenario* sc) {
  for (std::size_t k = 0; k < sc->samples.size(); ++k) {
    const coral::RelativeCheckResult& r = rel[sc->samples[k]];
    const double pr = r.valid ? coral::relativeProbability(r, rcfg) : kNaN;
    sc->p[1].push_back(pr);
    sc->p[2].push_back(std::isfinite(pr) && std::isfinite(sc->p[0][k]) ? std::min(pr, sc->p[0][k])
                                                                       : kNaN);
  }
  for (int m = 0; m < 3; ++m)
    for (const std::string g : {"all", kTranslationGroup, kRotationGroup}) {
      EvaluationRow row;
      row.method = coral::verdictMethodName(kVerdictMethods[m]);
      row.group = g;
      std::vector<int> scored;
      for (std::size_t k = 0; k < sc->samples.size(); ++k) {
        const Sample& s = set.samples[sc->samples[k]];
        if (s.label == 0 && g != "all" && s.group != g) continue;
        if (!std::isfinite(sc->p[m][k])) {
          ++row.skipped;
          continue;
        }
        row.scores.push_back(sc->p[m][k]);
        row.labels.push_back(s.label);
        scored.push_back(sc->samples[k]);
      }
      summarizeRow(set, scored, threshold, &row);
      sc->rows.push_back(row);
    }
}

std::vector<int> concat(const std::vector<Part>& parts, std::size_t except) {
  std::vector<int> out;
  for (std::size_t i = 0; i < parts.size(); ++i)
    if (i != except) out.insert(out.end(), parts[i].samples.begin(), parts[i].samples.end());
  return out;
}

}  // namespace

std::vector<coral::RelativeCheckResult> relativeResults(const SampleSet& set,
                                                        const coral::RelativeCheckConfig& cfg) {
  std::vector<coral::RelativeCheckResult> out;
  const int dim = set.methods.size() > 1 && set.methods[1].feature_names.size() == 7 ? 2 : 3;
  const std::vector<coral::ToleranceOffset> offsets =
      coral::toleranceOffsets(coral::ToleranceConfig(), dim);
  for (const Sample& s : set.samples) {
    const std::vector<double>& q = s.features[1];
    out.push_back(
        coral::decideRelative(q[0], offsets, std::vector<double>(q.begin() + 1, q.end()), cfg));
  }
  return out;
}

bool evaluateVerdicts(const SampleSet& set, const VerdictEvalConfig& cfg, VerdictEvaluation* out,
                      std::string* error) {
  if (const std::string e = cfg.validate(); !e.empty()) return coral::fail(error, e);
  const std::vector<MethodSpec> expect2 = verdictMethods(2), expect3 = verdictMethods(3);
  auto same = [&](const std::vector<MethodSpec>& e) {
    if (set.methods.size() != e.size()) return false;
    for (std::size_t m = 0; m < e.size(); ++m)
      if (set.methods[m].name != e[m].name || set.methods[m].feature_names != e[m].feature_names)
        return false;
    return true;
  };
  if (!same(expect2) && !same(expect3))
    return coral::fail(error, "not a verdict sample set (methods CorAl and Relative expected)");
  if (set.samples.empty()) return coral::fail(error, "no samples");
  *out = VerdictEvaluation();
  const std::vector<Part> parts = dataParts(set);
  for (const Part& p : parts) out->datasets.push_back(p.name);
  const std::vector<coral::RelativeCheckResult> rel = relativeResults(set, cfg.relative);
  const coral::LogisticRegressionConfig& lr = cfg.evaluation.regression;
  const double t = lr.threshold;

  for (const Part& part : parts) {  // in-data-set: contiguous folds over its pairs
    std::vector<int> pairs;
    for (int i : part.samples) pairs.push_back(set.samples[i].pair);
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    const int np = static_cast<int>(pairs.size()), k = std::min(cfg.evaluation.folds, np);
    if (k < 2) continue;  // a single pair cannot be cross-validated
    VerdictScenario sc{"cv", std::to_string(k) + " folds of " + part.name, part.name, {}, {}, {}};
    for (int f = 0; f < k; ++f) {
      const int lo = pairs[f * np / k], hi = pairs[(f + 1) * np / k - 1];
      std::vector<int> train, test;
      for (int i : part.samples)
        (set.samples[i].pair >= lo && set.samples[i].pair <= hi ? test : train).push_back(i);
      classifierOpinions(set, train, test, lr, &sc.p[0]);
      sc.samples.insert(sc.samples.end(), test.begin(), test.end());
    }
    finishScenario(set, rel, cfg.relative, t, &sc);
    out->scenarios.push_back(std::move(sc));
  }
  for (std::size_t a = 0; a < parts.size() && parts.size() > 2; ++a)  // 2 parts: = LODO
    for (std::size_t b = 0; b < parts.size(); ++b) {
      if (a == b) continue;
      VerdictScenario sc{"cross", parts[a].name, parts[b].name, parts[b].samples, {}, {}};
      classifierOpinions(set, parts[a].samples, parts[b].samples, lr, &sc.p[0]);
      finishScenario(set, rel, cfg.relative, t, &sc);
      out->scenarios.push_back(std::move(sc));
    }
  int n_lodo = 0;
  for (std::size_t b = 0; b < parts.size() && parts.size() > 1; ++b) {
    VerdictScenario sc{"lodo", "all but " + parts[b].name, parts[b].name, parts[b].samples, {}, {}};
    classifierOpinions(set, concat(parts, b), parts[b].samples, lr, &sc.p[0]);
    finishScenario(set, rel, cfg.relative, t, &sc);
    for (int m = 0; m < 3; ++m) out->lodo_accuracy[m] += sc.rows[3 * m].accuracy;
    ++n_lodo;
    out->scenarios.push_back(std::move(sc));
  }
  for (int m = 0; m < 3 && n_lodo > 0; ++m) out->lodo_accuracy[m] /= n_lodo;
  // Ties (within 0.005) go to the cheaper method: the classifier needs 1 CorAl evaluation,
  // the other two 1 + 2 x axes; between those, the one without training.
  int best = 0;
  for (int m : {1, 2})
    if (out->lodo_accuracy[m] > out->lodo_accuracy[best] + 0.005) best = m;
  if (best == 2 && out->lodo_accuracy[1] >= out->lodo_accuracy[2] - 0.005) best = 1;
  out->best = kVerdictMethods[best];

  std::vector<int> all;
  for (std::size_t i = 0; i < set.samples.size(); ++i)
    if (finiteCoral(set.samples[i])) all.push_back(static_cast<int>(i));
  return fitSamples(set, 0, all, lr, &out->classifier, error);
}

}  // namespace eval
}  // namespace coral_introspection
