#include "coral_introspection/online/self_calibration.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "coral_introspection/coral/logistic_regression.hpp"
#include "coral_introspection/coral/metrics.hpp"
#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace online {

std::string SelfCalibrationConfig::validate() const {
  return coral::Problems()
      .require(fraction_of_pairs > 0.0 && fraction_of_pairs <= 1.0, "fraction_of_pairs",
               "in (0, 1]", fraction_of_pairs)
      .require(max_samples >= 20 && max_samples <= 1000000, "max_samples", "in [20, 1e6]",
               max_samples)
      .require(min_samples_before_use >= 1 && min_samples_before_use <= max_samples,
               "min_samples_before_use", "in [1, max_samples]", min_samples_before_use)
      .require(min_auc >= 0.5 && min_auc <= 1.0, "min_auc", "in [0.5, 1]", min_auc)
      .require(holdout_fraction > 0.0 && holdout_fraction < 1.0, "holdout_fraction", "in (0, 1)",
               holdout_fraction)
      .require(prior_weight >= 0.0 && std::isfinite(prior_weight), "prior_weight",
               "finite and >= 0", prior_weight)
      .require(accept_score >= -1.0 && accept_score <= 0.0, "accept_score", "in [-1, 0]",
               accept_score)
      .str();
}

namespace {
// True for the calls where floor(n * f) steps: exactly floor(n * f) of the first n calls,
// evenly spread (the fraction of pairs and the hold-out share).
bool everyFraction(uint64_t n, double f) { return std::floor((n + 1) * f) > std::floor(n * f); }
}  // namespace

SelfCalibration::SelfCalibration(const SelfCalibrationConfig& cfg,
                                 const coral::ClassifierConfig& prior)
    : cfg_(cfg), prior_(prior) {
  status_.classifier = prior;
}

void SelfCalibration::setPrior(const coral::ClassifierConfig& prior) {
  prior_ = prior;
  if (status_.refits == 0) status_.classifier = prior;
  status_.classifier.threshold = prior.threshold;  // t_h is the user's choice, not fitted
}

void SelfCalibration::clearSamples() {
  pairs_.clear();
  status_.samples = status_.training_samples = status_.heldout_samples = 0;
  status_.heldout_auc = std::numeric_limits<double>::quiet_NaN();
  status_.in_use = false;
  status_.classifier = prior_;
}

bool SelfCalibration::select() {
  return everyFraction(status_.pairs_offered++, cfg_.fraction_of_pairs) &&
         ++status_.pairs_selected > 0;
}

bool SelfCalibration::addPair(const coral::CoralPair& pair, const Eigen::Isometry3d& T_ref_cur,
                              const coral::CoralResult& at_pose,
                              const coral::VerdictConfig& verdict) {
  if (!at_pose.valid) return false;
  const auto start = std::chrono::steady_clock::now();
  tolerance_ = verdict.tolerance;
  const std::vector<coral::ToleranceOffset> offsets =
      coral::toleranceOffsets(verdict.tolerance, pair.config().dimension);
  const std::vector<coral::CoralResult> moved = coral::neighbourResults(pair, T_ref_cur, offsets);
  status_.extra_evaluations += moved.size();
  std::vector<double> q;
  std::vector<CalibrationSample> negatives;
  for (const coral::CoralResult& r : moved) {
    q.push_back(r.valid ? r.quality : std::numeric_limits<double>::quiet_NaN());
    if (r.valid) negatives.push_back({r.h_joint, r.h_sep, 0});
  }
  // Acceptance by the training-free relative check on these same evaluations: the pose is a
  // clear minimum of Q (Eq. 5) along every axis. The classifier never votes on its samples.
  const coral::RelativeCheckResult rel =
      coral::decideRelative(at_pose.quality, offsets, q, verdict.relative);
  const bool accepted = rel.valid && rel.score <= cfg_.accept_score && !negatives.empty();
  if (accepted) addAcceptedPair({at_pose.h_joint, at_pose.h_sep, 1}, negatives);
  status_.seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return accepted;
}

void SelfCalibration::addAcceptedPair(const CalibrationSample& aligned,
                                      const std::vector<CalibrationSample>& misaligned) {
  PairSamples p;
  p.heldout = everyFraction(status_.pairs_accepted++, cfg_.holdout_fraction);
  p.samples.push_back(aligned);
  p.samples.insert(p.samples.end(), misaligned.begin(), misaligned.end());
  status_.samples += p.samples.size();
  pairs_.push_back(std::move(p));
  // Bounded memory: the oldest pairs go first (the scene and sensor of the recent past
  // describe the next pairs best).
  while (status_.samples > static_cast<std::size_t>(cfg_.max_samples) && pairs_.size() > 1) {
    status_.samples -= pairs_.front().samples.size();
    pairs_.pop_front();
  }
  refit();
}

void SelfCalibration::refit() {
  std::vector<const CalibrationSample*> train, test;
  for (const PairSamples& p : pairs_)
    for (const CalibrationSample& s : p.samples) (p.heldout ? test : train).push_back(&s);
  status_.training_samples = train.size();
  status_.heldout_samples = test.size();
  Eigen::MatrixXd X(train.size(), 2);
  std::vector<int> y;
  int positives = 0;
  for (std::size_t i = 0; i < train.size(); ++i) {
    X(i, 0) = train[i]->h_joint;  // x1 = H_joint, x2 = H_sep (Eq. 9), as coral_train
    X(i, 1) = train[i]->h_sep;
    y.push_back(train[i]->label);
    positives += train[i]->label;
  }
  if (positives == 0 || positives == static_cast<int>(train.size())) return;  // wait for both
  coral::LogisticRegressionConfig lr;  // balanced class weights (Sec. III-F), as coral_train
  lr.threshold = prior_.threshold;
  lr.prior_weight = cfg_.prior_weight;
  lr.prior_beta = Eigen::Vector3d(prior_.beta0, prior_.beta1, prior_.beta2);
  coral::LogisticModel model;
  std::string error;
  if (!coral::fitLogisticRegression(X, y, {}, lr, &model, &error)) {
    ++status_.refit_failures;
    status_.last_error = "refit: " + error;
    return;
  }
  ++status_.refits;
  status_.classifier = model.toClassifierConfig();
  std::vector<double> scores;
  std::vector<int> labels;
  const coral::ClassifierConfig& k = status_.classifier;
  for (const CalibrationSample* s : test) {
    // The logit z of Eq. 9 ranks like p but does not saturate (p rounds to 1 beyond z ~ 37,
    // which would turn a far-off classifier's ranking into ties).
    scores.push_back(k.beta0 + k.beta1 * s->h_joint + k.beta2 * s->h_sep);
    labels.push_back(s->label);
  }
  status_.heldout_auc = coral::auc(scores, labels);  // NaN until both classes are held out
  status_.in_use = static_cast<int>(train.size()) >= cfg_.min_samples_before_use &&
                   status_.heldout_auc >= cfg_.min_auc;
  if (!cfg_.output_file.empty()) writeYaml();
}

void SelfCalibration::writeYaml() {
  std::ostringstream c;
  c << "online self-calibration: " << status_.training_samples << " training and "
    << status_.heldout_samples << " held-out samples, held-out AUC " << status_.heldout_auc
    << ", refit " << status_.refits << (status_.in_use ? " (in use)" : " (not yet in use)");
  const std::vector<std::string> comments = {
      "CorAl alignment classifier (paper Sec. III-F, Eq. 9-10) refitted online by CoralNodelet",
      "(calibration/enabled): aligned = pairs the relative check finds a clear minimum of Q,",
      "misaligned = the same pairs moved by the tolerance; prior = the configured classifier.",
      c.str(), "Load into the nodelet's private namespace: <rosparam file=\"...\"/>"};
  const std::string tmp = cfg_.output_file + ".tmp";
  std::ofstream f(tmp);
  f << coral::classifierYaml(status_.classifier, comments, &tolerance_);
  f.close();
  if (!f || std::rename(tmp.c_str(), cfg_.output_file.c_str()) != 0)
    status_.last_error = "cannot write " + cfg_.output_file;
}

}  // namespace online
}  // namespace coral_introspection
