// Online self-calibration of the alignment classifier: the paper's self-supervised training
// (Sec. III-F) done live. For a bounded fraction of the judged pairs, CorAl is also evaluated
// at the pose moved by one tolerance along each axis (tolerance.hpp). A pair counts as
// accepted (its pose taken as correct) when the training-free relative check, run on exactly
// these evaluations, finds the pose a clear minimum of Q along every axis: never by the
// classifier being calibrated (no circularity). An accepted pair gives one aligned sample
// (H_joint, H_sep at the pose) and one misaligned sample per valid neighbour. The classifier
// (Eq. 9) is refitted on a bounded set of these samples with the preset's classifier as a
// Gaussian prior, its AUC is measured on held-out pairs, and it is written as a classifier
// YAML (coral::classifierYaml) that loads as-is later. ROS-free; not thread-safe (the
// Introspector owns it).
#pragma once

#include <cstdint>
#include <deque>
#include <limits>
#include <string>
#include <vector>

#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/coral/verdict.hpp"

namespace coral_introspection {
namespace online {

struct SelfCalibrationConfig {
  bool enabled = false;
  // [-] share of judged pairs (with a valid CorAl result) that get the extra CorAl
  // evaluations: 2 x axes each (6 in 2D, 12 in 3D), i.e. on average fraction x 2 x axes
  // extra evaluations per pair. Chosen deterministically: after n pairs exactly
  // floor(n x fraction) were taken. 0.25 in 3D costs 3 evaluations per pair on average.
  double fraction_of_pairs = 0.25;
  // [samples] memory bound (aligned + misaligned, held-out included): the oldest pairs are
  // dropped first. 2000 samples = 154 3D pairs or 285 2D pairs, about 50 kB.
  int max_samples = 2000;
  // [samples] training samples (held-out excluded) before the refitted classifier judges
  // instead of the configured one; with fewer the prior would dominate anyway.
  int min_samples_before_use = 100;
  // [-] held-out AUC the refit must reach before it judges (and otherwise stops judging).
  double min_auc = 0.9;
  // [-] share of accepted pairs held out of the fit for the AUC, whole pairs (a pair's
  // aligned and misaligned samples never straddle the split); deterministic like the fraction.
  double holdout_fraction = 0.25;
  // [-] precision of the Gaussian prior toward the configured classifier, in standardized
  // coordinates (coral::LogisticRegressionConfig::prior_weight). The penalty is quadratic in
  // the distance to the prior, so a far-off prior (a classifier trained elsewhere, or a wrong
  // one) takes long to fade with a large weight: 1 keeps early fits near a sensible prior
  // and lets a wrong one go within some tens of pairs (doc/self_calibration.md).
  double prior_weight = 1.0;
  // [-] a pair is accepted when the relative check's score (max over axes of s_k, see
  // coral::RelativeCheckConfig) is at most this: every axis' lower neighbour higher than Q at
  // the pose. -0.2 mirrors the verdict margin 0.2: the clear-margin side of "aligned".
  double accept_score = -0.2;
  // Classifier YAML rewritten after each successful refit (atomically: temp file + rename);
  // empty = not written.
  std::string output_file;
  std::string validate() const;  // empty when valid
};

struct CalibrationSample {
  double h_joint = 0.0;  // x1 of Eq. 9 [nats]
  double h_sep = 0.0;    // x2 of Eq. 9 [nats]
  int label = 1;         // 1 aligned, 0 misaligned by the tolerance
};

struct CalibrationStatus {
  uint64_t pairs_offered = 0;      // pairs seen by select()
  uint64_t pairs_selected = 0;     // given the extra evaluations (fraction)
  uint64_t pairs_accepted = 0;     // relative check clearly aligned: samples kept
  uint64_t extra_evaluations = 0;  // CorAl evaluations beyond the verdict's own
  uint64_t refits = 0, refit_failures = 0;
  std::size_t samples = 0, training_samples = 0, heldout_samples = 0;  // currently held
  double heldout_auc = std::numeric_limits<double>::quiet_NaN();       // of the last refit
  bool in_use = false;  // the refitted classifier judges (enough samples, AUC >= min_auc)
  coral::ClassifierConfig classifier;  // last refit (the prior before the first)
  double seconds = 0.0;                // [s] wall time spent in addPair (evaluations + fits)
  std::string last_error;              // last refit or write failure
};

class SelfCalibration {
 public:
  // Preconditions: cfg.validate() and prior.validate() are empty.
  SelfCalibration(const SelfCalibrationConfig& cfg = SelfCalibrationConfig(),
                  const coral::ClassifierConfig& prior = coral::ClassifierConfig());
  // The configured classifier changed: it becomes the prior (samples are kept).
  void setPrior(const coral::ClassifierConfig& prior);
  // Forgets every sample and the refit (e.g. CorAl settings changed the features).
  void clearSamples();

  // Once per judged pair: true when this pair gets the extra evaluations (fraction_of_pairs).
  bool select();
  // The extra evaluations of a selected pair (prepared by its verdict: ref in the common
  // frame, cur in its own sensor frame), at_pose = CorAl at T_ref_cur. Accepts or not, then
  // refits. Returns true when the pair was accepted.
  bool addPair(const coral::CoralPair& pair, const Eigen::Isometry3d& T_ref_cur,
               const coral::CoralResult& at_pose, const coral::VerdictConfig& verdict);
  // The samples of one accepted pair (addPair's second half, also for tests); refits.
  void addAcceptedPair(const CalibrationSample& aligned,
                       const std::vector<CalibrationSample>& misaligned);

  const CalibrationStatus& status() const { return status_; }
  // The classifier the verdict should use: the refit when in_use, else the prior.
  const coral::ClassifierConfig& classifier() const {
    return status_.in_use ? status_.classifier : prior_;
  }

 private:
  struct PairSamples {
    bool heldout = false;
    std::vector<CalibrationSample> samples;
  };
  void refit();
  void writeYaml();

  SelfCalibrationConfig cfg_;
  coral::ClassifierConfig prior_;
  std::deque<PairSamples> pairs_;
  CalibrationStatus status_;
  coral::ToleranceConfig tolerance_;  // of the last pair (written into the YAML)
};

}  // namespace online
}  // namespace coral_introspection
