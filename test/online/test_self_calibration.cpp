// online::SelfCalibration with known answers: the fraction of pairs taken, bounded memory,
// separable features (held-out AUC near 1, the refit replaces a wrong classifier), the prior
// deciding with few samples and fading with many, acceptance by the relative check on a
// ray-cast pair, and an Introspector stream whose wrong classifier is corrected online.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include "coral_introspection/eval/synthetic.hpp"
#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/online/self_calibration.hpp"
#include "support/yard_pair.hpp"

using namespace coral_introspection;
using online::CalibrationSample;
using online::SelfCalibration;
using online::SelfCalibrationConfig;

namespace {

// Q = H_joint - H_sep (Eq. 5) at which p = 0.5, at H_sep = h_sep.
double boundaryQ(const coral::ClassifierConfig& c, double h_sep) {
  return -(c.beta0 + (c.beta1 + c.beta2) * h_sep) / c.beta1;
}

// One pair's samples: aligned Q ~ q_aligned, each of `n_neg` misaligned ~ q_misaligned, H_sep
// varying by scene (the dual entropy of the paper: H_sep absorbs the scene).
// With tilt t, Q of both classes also grows by t (H_sep - 3): the boundary is then
// H_joint - (1 + t) H_sep = const, i.e. direction ratio -beta2 / beta1 = 1 + t.
struct FeatureModel {
  double q_aligned = 0.05, q_misaligned = 0.45, spread = 0.03, tilt = 0.0;
  int n_neg = 6;
};
void addPairs(SelfCalibration* cal, const FeatureModel& m, int pairs, std::mt19937& rng) {
  std::normal_distribution<double> g;
  for (int k = 0; k < pairs; ++k) {
    const double h_sep = 3.0 + 0.3 * g(rng);
    const double shift = m.tilt * (h_sep - 3.0);
    const CalibrationSample pos{h_sep + shift + m.q_aligned + m.spread * g(rng), h_sep, 1};
    std::vector<CalibrationSample> neg;
    for (int i = 0; i < m.n_neg; ++i)
      neg.push_back({h_sep + shift + m.q_misaligned + m.spread * g(rng), h_sep, 0});
    cal->addAcceptedPair(pos, neg);
  }
}

coral::ClassifierConfig alwaysAligned() {  // a deliberately wrong classifier: p ~ 1 always
  coral::ClassifierConfig c;
  c.beta0 = 30.0;
  c.beta1 = -1.0;
  c.beta2 = 1.0;
  return c;
}

}  // namespace

TEST(SelfCalibration, FractionOfPairsIsHonouredExactlyAndEvenly) {
  SelfCalibrationConfig cfg;
  cfg.fraction_of_pairs = 0.3;
  SelfCalibration cal(cfg);
  int taken = 0, run = 0, longest_gap = 0;
  for (int n = 1; n <= 1000; ++n) {
    const bool t = cal.select();
    taken += t;
    run = t ? 0 : run + 1;
    longest_gap = std::max(longest_gap, run);
    EXPECT_EQ(taken, static_cast<int>(std::floor(n * 0.3 + 1e-9))) << n;
  }
  EXPECT_EQ(cal.status().pairs_offered, 1000u);
  EXPECT_EQ(cal.status().pairs_selected, 300u);
  EXPECT_LE(longest_gap, 3);  // never more than ceil(1 / 0.3) - 1 = 3 pairs in a row skipped
}

TEST(SelfCalibration, ValidateNamesTheParameter) {
  SelfCalibrationConfig cfg;
  EXPECT_EQ(cfg.validate(), "");
  cfg.fraction_of_pairs = 0.0;
  EXPECT_NE(cfg.validate().find("fraction_of_pairs must be in (0, 1] (got 0)"), std::string::npos);
  cfg = SelfCalibrationConfig();
  cfg.min_samples_before_use = cfg.max_samples + 1;
  EXPECT_NE(cfg.validate().find("min_samples_before_use"), std::string::npos);
}

TEST(SelfCalibration, SeparableFeaturesGiveHeldOutAucNearOneAndReplaceAWrongClassifier) {
  SelfCalibrationConfig cfg;
  cfg.min_samples_before_use = 100;
  cfg.output_file = ::testing::TempDir() + "/calib_classifier.yaml";
  SelfCalibration cal(cfg, alwaysAligned());
  std::mt19937 rng(3);
  addPairs(&cal, FeatureModel(), 10, rng);  // 10 pairs: 8 train (56 samples), 2 held out
  EXPECT_EQ(cal.status().training_samples, 56u);
  EXPECT_EQ(cal.status().heldout_samples, 14u);
  EXPECT_FALSE(cal.status().in_use);  // fewer than min_samples_before_use
  EXPECT_EQ(cal.classifier().beta0, 30.0);
  addPairs(&cal, FeatureModel(), 30, rng);
  const online::CalibrationStatus& s = cal.status();
  EXPECT_EQ(s.pairs_accepted, 40u);
  EXPECT_EQ(s.training_samples, 30u * 7);
  EXPECT_GE(s.heldout_auc, 0.999);
  EXPECT_TRUE(s.in_use);
  EXPECT_EQ(s.refits, 40u);
  // The boundary lies between the classes (Q 0.05 and 0.45): the refit judges fresh pairs
  // right, where the wrong prior called every misaligned one aligned.
  EXPECT_NEAR(boundaryQ(cal.classifier(), 3.0), 0.25, 0.1);
  std::normal_distribution<double> g;
  int right = 0, total = 0;
  for (int k = 0; k < 200; ++k) {
    const double h = 3.0 + 0.3 * g(rng);
    right += coral::classify(cal.classifier(), h + 0.05 + 0.03 * g(rng), h).aligned;
    right += !coral::classify(cal.classifier(), h + 0.45 + 0.03 * g(rng), h).aligned;
    total += 2;
  }
  EXPECT_GE(right, total - 2);
  // The YAML loads as a classifier (method classifier, tolerance it was calibrated for).
  std::ifstream f(cfg.output_file);
  std::stringstream text;
  text << f.rdbuf();
  EXPECT_NE(text.str().find("classifier:\n  method: classifier\n  beta0: "), std::string::npos);
  EXPECT_NE(text.str().find("tolerance:\n  translation: 0.3"), std::string::npos);
  EXPECT_NE(text.str().find("(in use)"), std::string::npos) << text.str();
}

// The prior acts on the slopes, i.e. on the direction of the boundary in the (H_joint, H_sep)
// plane (how much H_sep, the scene's own entropy, offsets H_joint): few pairs hardly show it
// (H_sep is one value per pair), so the preset's direction holds; hundreds of pairs with
// another direction override it. The boundary's position always comes from the data.
TEST(SelfCalibration, PriorHoldsTheDirectionWithFewPairsAndFadesWithMany) {
  coral::ClassifierConfig preset;  // -beta2 / beta1 = 1: boundary on Q alone
  FeatureModel tilted;             // the data's direction: 1.5
  tilted.tilt = 0.5;
  auto fit = [&](double weight, int pairs) {
    SelfCalibrationConfig cfg;
    cfg.prior_weight = weight;
    SelfCalibration cal(cfg, preset);
    std::mt19937 rng(11);
    addPairs(&cal, tilted, pairs, rng);
    EXPECT_EQ(cal.status().refits, static_cast<uint64_t>(pairs));
    return cal.status().classifier;
  };
  auto ratio = [](const coral::ClassifierConfig& c) { return -c.beta2 / c.beta1; };
  const coral::ClassifierConfig few = fit(10.0, 3), few_free = fit(0.0, 3);
  EXPECT_NEAR(ratio(few), 1.0, 0.15);
  EXPECT_GT(std::abs(ratio(few_free) - 1.0), 3.0 * std::abs(ratio(few) - 1.0))
      << ratio(few_free) << " vs " << ratio(few);
  const coral::ClassifierConfig many = fit(10.0, 300);
  EXPECT_NEAR(ratio(many), 1.5, 0.1);
  // Either way the boundary lies between the classes at the mean scene (Q 0.05 / 0.45).
  EXPECT_GT(boundaryQ(few, 3.0), 0.1);
  EXPECT_LT(boundaryQ(few, 3.0), 0.4);
  EXPECT_NEAR(boundaryQ(many, 3.0), 0.25, 0.1);
}

TEST(SelfCalibration, MemoryStaysBoundedDroppingTheOldestPairs) {
  SelfCalibrationConfig cfg;
  cfg.max_samples = 50;
  cfg.min_samples_before_use = 20;
  SelfCalibration cal(cfg);
  std::mt19937 rng(5);
  for (int k = 0; k < 100; ++k) {
    addPairs(&cal, FeatureModel(), 1, rng);
    EXPECT_LE(cal.status().samples, 50u);
    if (k >= 10) {
      EXPECT_GE(cal.status().samples, 44u);  // 50 - 7 + 1
    }
    EXPECT_EQ(cal.status().samples, cal.status().training_samples + cal.status().heldout_samples);
  }
  EXPECT_EQ(cal.status().pairs_accepted, 100u);
}

using coral_introspection::test::YardPair;

TEST(SelfCalibration, RelativeCheckAcceptsThePairAtTruthOnly) {
  const YardPair p = test::yardPair(1, 7, Eigen::Isometry3d::Identity());
  const coral::CoralConfig coral = test::planarYardCoral();
  coral::VerdictConfig v;
  v.tolerance = coral::ToleranceConfig::lidar2d();
  SelfCalibration cal;
  const coral::CoralResult truth =
      coral::computeCoral(p.a, coral::transformScan(p.b, p.T_a_b), coral);
  ASSERT_TRUE(truth.valid);
  const coral::CoralPair pair(p.a, p.b, coral);
  EXPECT_TRUE(cal.addPair(pair, p.T_a_b, truth, v));
  EXPECT_EQ(cal.status().extra_evaluations, 6u);  // x, y, yaw in both directions
  EXPECT_EQ(cal.status().samples, 7u);            // 1 aligned + 6 misaligned
  // Two tolerances off along x: the pose is no minimum of Q, nothing is learnt from it.
  const Eigen::Isometry3d off = p.T_a_b * coral::se2(0.6, 0.0, 0.0);
  const coral::CoralResult at_off = coral::computeCoral(p.a, coral::transformScan(p.b, off), coral);
  ASSERT_TRUE(at_off.valid);
  EXPECT_FALSE(cal.addPair(pair, off, at_off, v));
  EXPECT_EQ(cal.status().extra_evaluations, 12u);
  EXPECT_EQ(cal.status().samples, 7u);
  EXPECT_EQ(cal.status().pairs_accepted, 1u);
}

// A planar lidar stream through the yard with a wrong classifier (every pair aligned) and
// an odometry error on every fifth scan: with calibration the errors are caught once the
// refit is in use, never before.
TEST(SelfCalibration, IntrospectorCorrectsAWrongClassifierOnline) {
  online::IntrospectorConfig cfg;
  cfg.coral = test::planarYardCoral();
  cfg.verdict.tolerance = coral::ToleranceConfig::lidar2d();
  cfg.verdict.classifier = alwaysAligned();
  cfg.calibration.enabled = true;
  cfg.calibration.fraction_of_pairs = 1.0;
  cfg.calibration.min_samples_before_use = 60;
  ASSERT_EQ(cfg.validate(), "");
  online::Introspector intro(cfg);
  std::mt19937 rng(9);
  eval::LidarModel lidar;
  lidar.rings = 1;
  lidar.v_min_deg = lidar.v_max_deg = 0.0;
  const auto scene = eval::SyntheticScene::structuredYard();
  int right_before = 0, wrong_before = 0, right_after = 0, wrong_after = 0, first_use = -1;
  int bad_pairs = 0, clean_accepted = 0, bad_accepted = 0;
  for (int k = 0; k < 60; ++k) {
    // Back and forth along the yard (x in [-8, 8]), turning slowly.
    const double s = std::fmod(0.35 * k, 32.0), x = s < 16.0 ? -8.0 + s : 24.0 - s;
    const Eigen::Isometry3d truth =
        coral::se2(x, -1.0 + 0.5 * std::sin(0.3 * k), 0.1 * std::sin(0.2 * k));
    const bool bad = k % 5 == 4;
    online::ScanInput in;
    in.stamp = 0.1 * k;
    in.features.points = eval::simulateScan(scene, truth, lidar, rng);
    in.T_fixed_sensor = bad ? truth * coral::se2(0.0, 0.3, 0.0) : truth;  // 1 tolerance
    const bool in_use = intro.calibration().status().in_use;
    if (in_use && first_use < 0) first_use = k;
    const online::Report r = intro.process(std::move(in));
    const uint64_t accepted = intro.calibration().status().pairs_accepted;
    intro.calibrate();
    if (!r.judged) continue;
    ASSERT_TRUE(r.hasVerdict()) << k << ": " << r.reason;
    const bool expect_aligned = !bad && k % 5 != 0;  // (k-1, k) touches no bad scan
    bad_pairs += !expect_aligned;
    const bool took = intro.calibration().status().pairs_accepted > accepted;
    (expect_aligned ? clean_accepted : bad_accepted) += took;
    const bool right = r.pair.verdict.aligned == expect_aligned;
    (in_use ? right_after : right_before) += right;
    (in_use ? wrong_after : wrong_before) += !right;
  }
  const online::CalibrationStatus& s = intro.calibration().status();
  EXPECT_EQ(bad_pairs, 23);  // 12 bad scans, each in two pairs but the last one
  EXPECT_EQ(s.pairs_selected, 59u);
  EXPECT_EQ(s.extra_evaluations, 59u * 6);
  EXPECT_EQ(bad_accepted, 0);     // a wrong pose never becomes an "aligned" sample
  EXPECT_GE(clean_accepted, 30);  // of 36 clean pairs
  EXPECT_GE(s.heldout_auc, 0.95);
  ASSERT_GE(first_use, 0) << "calibration never reached min_samples / min_auc";
  EXPECT_LE(first_use, 20);                  // stated: in use within the first 20 scans
  EXPECT_GT(wrong_before, 0);                // the wrong classifier missed the errors
  EXPECT_EQ(wrong_after, 0) << right_after;  // afterwards every verdict is right
  EXPECT_GE(right_after, 35);
}
