// The verdict path of check_alignment and of the stream (online::judgePair with the
// preset's parameters as the nodelet loads them, no classifier override) on every shared
// real pair of each preset's sensor class: at ground truth the pair must be judged aligned,
// with the later scan moved by one tolerance forward, backward, left or right (its sensor
// frame) misaligned. Every pair of every data set (the Livox keyframes' 313 pairs take
// 24-35 s). Where it does not hold (ACES corridors), each pair is classed by what CorAl
// itself shows at ground truth (doc/verdict_pairs.md): the test asserts that every pair of
// the clear class is right and bounds the documented exceptions.
// CORAL_VERDICT_PAIR_STRIDE=N (scripts/ci/test_sanitizers.sh) judges every N-th pair of each
// data set only: the sanitizer build is ~55x slower; the counts measured on all pairs are
// then replaced by what must hold for any subset (every pair right, every clear pair right).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <iomanip>
#include <sstream>
#include <vector>

#include "coral_introspection/eval/cloud_io.hpp"
#include "coral_introspection/eval/error_sweep.hpp"
#include "coral_introspection/eval/evaluation.hpp"
#include "coral_introspection/eval/pair_datasets.hpp"
#include "coral_introspection/eval/sample_csv.hpp"
#include "coral_introspection/eval/verdict_evaluation.hpp"
#include "coral_introspection/eval/verdict_samples.hpp"
#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/ros_eval/preset_file.hpp"
#include "support/preset.hpp"
#include "support/test_data.hpp"

using namespace coral_introspection;

namespace {

const char* const kCases[5] = {"ground truth", "forward", "backward", "left", "right"};

// Every stride()-th pair is judged (1 = all; coral_test::pairStride).
std::size_t stride() { return coral_test::pairStride(); }
// Pairs judged of a data set of n pairs.
int judged(int n) {
  return static_cast<int>((static_cast<std::size_t>(n) + stride() - 1) / stride());
}

// What CorAl shows at ground truth, from the relative check's probes there (Q one tolerance
// away along each axis, which include the four offsets judged here):
enum PairClass {
  kClear,      // every neighbour's Q is above Q at ground truth, no flat axis
  kFlat,       // Q ordering holds, but an axis is flat (unobservable, e.g. along a corridor)
  kQOrder,     // some neighbour's Q <= Q at ground truth: CorAl itself ranks that offset at
               // least as well aligned as the relation, so a verdict that calls the pose of
               // lower Q aligned cannot be right on both
  kNoVerdict,  // no valid relative check at ground truth
  kClasses
};
const char* const kClassNames[kClasses] = {"clear", "flat axis", "Q order", "no verdict"};

PairClass classify(const coral::AlignmentVerdict& gt) {
  const coral::RelativeCheckResult& r = gt.relative;
  if (!gt.valid || !r.valid) return kNoVerdict;
  for (const coral::AxisProbe& p : r.axes)
    for (double qn : {p.q_plus, p.q_minus})
      if (std::isfinite(qn) && qn <= r.q) return kQOrder;
  return r.flat_axes.empty() ? kClear : kFlat;
}

struct Tally {
  int pairs = 0;
  int right[5] = {0, 0, 0, 0, 0};  // per case of kCases: verdict as expected
  int class_pairs[kClasses] = {0, 0, 0, 0};
  int class_wrong[kClasses] = {0, 0, 0, 0};  // wrong verdicts (of the five) per class
  std::ostringstream wrong;                  // one line per pair with a wrong verdict (printed)
  bool allRight() const {
    for (int c = 0; c < 5; ++c)
      if (right[c] != pairs) return false;
    return true;
  }
};

void loadData(const ros_adapters::NodeConfig& node, const std::string& spec_text,
              eval::PairDataset* d) {
  std::string err;
  eval::DatasetSpec spec;
  ASSERT_TRUE(eval::parseDatasetSpec(spec_text, &spec, &err)) << err;
  eval::DatasetOptions opt;
  opt.oxford.rip = node.rip;
  opt.oxford.with_cfear = false;
  opt.oxford.motion_compensation = node.online.deskew.enabled;
  ASSERT_TRUE(eval::loadPairDataset(spec, opt, nullptr, d, &err)) << err;
}

// Preset `preset` and the data set of `spec_text` for it; false (a fatal failure recorded) when
// either cannot be loaded.
bool loadPresetData(const std::string& preset, const std::string& spec_text,
                    ros_adapters::NodeConfig* node, eval::PairDataset* d) {
  coral_test::loadPreset(preset, node);
  loadData(*node, spec_text, d);
  return !::testing::Test::HasFatalFailure();
}

// Q one tolerance away along `axis` minus Q at ground truth, over the pair's largest axis
// sensitivity (NaN when not probed).
double relativeStep(const coral::RelativeCheckResult& r, coral::Axis axis, int sign) {
  for (const coral::AxisProbe& p : r.axes)
    if (p.axis == axis && r.scale > 0.0) return ((sign > 0 ? p.q_plus : p.q_minus) - r.q) / r.scale;
  return std::nan("");
}

// One line of the per-pair table (doc/verdict_pairs.md) for a pair with a wrong verdict.
void describe(std::size_t i, const eval::PairDataset& d, const coral::AlignmentVerdict& gt,
              PairClass cls, const bool ok[5], std::ostream& out) {
  const eval::ScanPair& p = d.pairs[i];
  out << "  pair " << i << " (stamps " << std::fixed << std::setprecision(2) << d.scans[p.a].stamp
      << " " << d.scans[p.b].stamp << ") " << kClassNames[cls] << "; wrong:";
  for (int c = 0; c < 5; ++c)
    if (!ok[c]) out << " " << kCases[c] << ";";
  out << " flat:";
  for (coral::Axis a : gt.relative.flat_axes) out << " " << coral::axisName(a);
  out << "; Q <= Q(ground truth) at:";
  for (const coral::AxisProbe& a : gt.relative.axes)
    for (int sign : {1, -1})
      if ((sign > 0 ? a.q_plus : a.q_minus) <= gt.relative.q)
        out << " " << coral::axisName(a.axis) << (sign > 0 ? "+" : "-");
  out << std::setprecision(4) << "; (Q(x+) - Q)/S " << relativeStep(gt.relative, coral::Axis::kX, 1)
      << ", (Q(x-) - Q)/S " << relativeStep(gt.relative, coral::Axis::kX, -1) << ", S "
      << gt.relative.scale << " nats; overlap " << std::setprecision(2) << gt.coral.overlap << "\n"
      << std::defaultfloat;
}

// Judges every pair of `spec` with `preset`.
void judgeDataSet(const std::string& preset, const std::string& spec_text, Tally* t) {
  ros_adapters::NodeConfig node;
  eval::PairDataset d;
  if (!loadPresetData(preset, spec_text, &node, &d)) return;
  const coral::VerdictConfig& verdict = node.online.verdict;
  const double m = verdict.tolerance.translation;
  const coral::Vec3 offsets[5] = {{0, 0, 0}, {m, 0, 0}, {-m, 0, 0}, {0, m, 0}, {0, -m, 0}};
  const std::size_t step = stride();
  for (std::size_t i = 0; i < d.pairs.size(); i += step) {
    const eval::ScanPair& p = d.pairs[i];
    ++t->pairs;
    coral::AlignmentVerdict gt;
    bool ok[5];
    for (int c = 0; c < 5; ++c) {
      Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
      delta.translation() = offsets[c];
      const coral::AlignmentVerdict v = online::judgePair(d.scans[p.a].scan, d.scans[p.b].scan,
                                                          p.T_a_b * delta, node.online, false)
                                            .verdict;
      if (c == 0) gt = v;
      ok[c] = v.valid && v.aligned == (c == 0);
      t->right[c] += ok[c];
    }
    const PairClass cls = classify(gt);
    ++t->class_pairs[cls];
    const int wrong = 5 - static_cast<int>(std::count(ok, ok + 5, true));
    t->class_wrong[cls] += wrong;
    if (wrong > 0) describe(i, d, gt, cls, ok, t->wrong);
  }
  std::cout << preset << " (" << verdictMethodName(verdict.method) << ") on " << d.name << ", "
            << t->pairs << " pairs, right:";
  for (int c = 0; c < 5; ++c) std::cout << " " << kCases[c] << " " << t->right[c];
  std::cout << "\n  classes at ground truth (pairs / wrong verdicts):";
  for (int k = 0; k < kClasses; ++k)
    std::cout << " " << kClassNames[k] << " " << t->class_pairs[k] << " / " << t->class_wrong[k]
              << ";";
  std::cout << "\n" << t->wrong.str();
}

}  // namespace

// The online verdict (online::judgePair, which check_alignment and the stream call) equals
// coral_train's evaluation of the same samples: same Q values, relative score, verdict and
// classifier probability, for every method.
TEST(PresetVerdicts, OnlineVerdictEqualsTrainingEvaluation) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  ros_adapters::NodeConfig node;
  coral_test::loadPreset("radar_oxford", &node);
  eval::PairDataset d;
  loadData(node, "oxford:" + coral_data, &d);
  ASSERT_FALSE(::testing::Test::HasFatalFailure());
  eval::VerdictSampleConfig scfg;
  scfg.coral = node.online.coral;
  scfg.tolerance = node.online.verdict.tolerance;
  eval::SampleSet set;
  std::string err;
  ASSERT_TRUE(eval::buildVerdictSamples(d.name, d.scans, d.pairs, scfg, nullptr, &set, &err))
      << err;
  const std::vector<coral::RelativeCheckResult> rel =
      eval::relativeResults(set, node.online.verdict.relative);
  const std::vector<coral::ToleranceOffset> offsets =
      coral::toleranceOffsets(scfg.tolerance, scfg.coral.dimension);
  ASSERT_EQ(set.samples.size(), d.pairs.size() * (offsets.size() + 1));
  int misaligned = 0;
  for (coral::VerdictMethod m : {coral::VerdictMethod::kClassifier, coral::VerdictMethod::kRelative,
                                 coral::VerdictMethod::kBoth, coral::VerdictMethod::kGated}) {
    online::IntrospectorConfig cfg = node.online;
    cfg.verdict.method = m;
    for (std::size_t k = 0; k < set.samples.size(); ++k) {
      const eval::Sample& s = set.samples[k];
      const int o = static_cast<int>(k % (offsets.size() + 1)) - 1;  // -1: aligned sample
      const eval::ScanPair& p = d.pairs[s.pair];
      const online::PairJudgement j = online::judgePair(
          d.scans[p.a].scan, d.scans[p.b].scan,
          p.T_a_b * (o < 0 ? Eigen::Isometry3d::Identity() : offsets[o].delta), cfg, false);
      SCOPED_TRACE("pair " + std::to_string(s.pair) + " " + (o < 0 ? "aligned" : offsets[o].name) +
                   " " + coral::verdictMethodName(m));
      ASSERT_TRUE(j.verdict.valid) << j.reason;
      EXPECT_EQ(j.verdict.coral.h_joint, s.features[0][0]);
      EXPECT_EQ(j.verdict.coral.h_sep, s.features[0][1]);
      const coral::Verdict c =
          coral::classify(cfg.verdict.classifier, s.features[0][0], s.features[0][1]);
      EXPECT_EQ(j.verdict.classifier.probability, c.probability);
      if (m != coral::VerdictMethod::kClassifier) {
        EXPECT_EQ(j.verdict.relative.score, rel[k].score);
        EXPECT_EQ(j.verdict.relative.misaligned, rel[k].misaligned);
        EXPECT_EQ(j.verdict.relative.hint.name, rel[k].hint.name);
      }
      const bool rel_aligned = !rel[k].misaligned;
      const coral::GateConfig& gate = cfg.verdict.gate;
      const bool gate_passed =
          c.probability >= gate.min_probability && j.verdict.coral.overlap >= gate.min_overlap;
      const bool expect = m == coral::VerdictMethod::kClassifier ? c.aligned
                          : m == coral::VerdictMethod::kRelative ? rel_aligned
                          : m == coral::VerdictMethod::kBoth     ? c.aligned && rel_aligned
                                                                 : rel_aligned && gate_passed;
      EXPECT_EQ(j.verdict.aligned, expect);
      misaligned += !j.verdict.aligned;
    }
  }
  EXPECT_GT(misaligned, 0);  // both outcomes occur, so the comparison means something
}

TEST(PresetVerdicts, RadarOxfordOnTheOxfordPairs) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  Tally t;
  judgeDataSet("radar_oxford", "oxford:" + coral_data, &t);
  EXPECT_EQ(t.pairs, judged(10));
  EXPECT_TRUE(t.allRight()) << "(pairs listed above)";
}

TEST(PresetVerdicts, Lidar3dOnTheLibpointmatcherPair) {
  CORAL_REQUIRE_DATA("libpointmatcher_car_cloud");
  Tally t;
  judgeDataSet("lidar_3d", "cloudlist:" + coral_data + "/carCloudList.csv", &t);
  EXPECT_EQ(t.pairs, judged(1));
  EXPECT_TRUE(t.allRight()) << "(pairs listed above)";
}

TEST(PresetVerdicts, Lidar3dOnTheLivoxKeyframes) {
  CORAL_REQUIRE_DATA("hku1_livox_keyframes");
  Tally t;
  judgeDataSet("lidar_3d", "keyframes:" + coral_data, &t);
  EXPECT_EQ(t.pairs, judged(313));
  EXPECT_TRUE(t.allRight()) << "(pairs listed above)";
}

TEST(PresetVerdicts, Lidar2dOnTheAcesRelations) {
  CORAL_REQUIRE_DATA("radish_aces");
  Tally t;
  judgeDataSet("lidar_2d", "carmen:" + coral_data + "/aces.clf.bz2", &t);
  EXPECT_EQ(t.pairs, judged(1279));
  // Every clear pair (Q ordering holds, no flat axis at ground truth) is right in all five
  // cases but five; measured 954 clear pairs. Pair 1228, a loop-closure relation (stamps
  // 481.8 and 1078.5) whose scans overlap by 9 %: the gate (classifier p 3.6e-4 < 0.01)
  // rejects it at ground truth. Pairs 313 and 828: the coarse probe finds Q lower by 0.024 a
  // half turn away and by 0.069 two tolerances along -x (coral_error_sweep's coarse_step).
  // Pairs 1226 and 1230, loop relations whose scans overlap by 0.11 and 0.09: the gate's
  // overlap bound (0.25, 2026-12-05). Pairs 405 (consecutive scans) and 1268 (a loop
  // relation): the gate's free-space bound (0.08, 2026-12-05; conflicts 0.094 and 0.151).
  // Pair 1270 (a loop relation, overlap 0.35): the gate's constraint bound (0.04, 2026-12-05;
  // 0.014).
  EXPECT_LE(t.class_wrong[kClear], 8) << "(pairs listed above)";
  EXPECT_EQ(t.class_pairs[kNoVerdict], 0);
  if (stride() > 1) {  // a subset: the counts below were measured on all pairs
    EXPECT_GT(t.class_pairs[kClear], t.pairs / 2);
    return;
  }
  EXPECT_GE(t.class_pairs[kClear], 954);
  // The exceptions, pair by pair with an ICP check of each relation in doc/verdict_pairs.md.
  // Measured: Q order 42 pairs, 67 wrong verdicts (41 of the pairs along x, 39 of them with x
  // flat; in 8 ICP also puts the relation >= 0.15 m off towards the offset CorAl prefers; 4
  // are loop closures with overlap < 0.6); flat axis 283 pairs (x in all), 14 wrong verdicts:
  // an offset along x whose Q is only 0.03-1.3 % of the pair's largest axis sensitivity above
  // Q at the relation, within the relative check's margin (in 2 of them ICP puts the relation
  // 0.21-0.26 m towards that offset).
  EXPECT_LE(t.class_pairs[kQOrder], 42) << "(pairs listed above)";
  // Flat axis: 15 since the coarse probe (pair 836: registered from the relation, b ends 1.3
  // tolerances away with Q lower by 0.020); 17 since the constraint bound (pairs 794 and 953,
  // consecutive scans in a corridor: constraint 0.038 and 0.037 < 0.04).
  EXPECT_LE(t.class_wrong[kFlat], 17) << "(pairs listed above)";
  // Measured: ground truth 1243 (1250 with the relative check alone: the gate rejects pair
  // 1228 above and Q-order pair 780, classifier p 1.2e-7; 1248 before the coarse probe, which
  // rejects 313, 828 and 836; 1245 before the overlap bound, which rejects 1226 and 1230;
  // 1243 before the free-space bound, which rejects 405 and 1268; 1241 before the constraint
  // bound, which rejects 794, 953 and 1270), forward 1271 (1268 before the constraint
  // bound), backward 1242 (1241), left 1279, right 1279.
  EXPECT_GE(t.right[0], 1238) << "(pairs listed above)";
  EXPECT_GE(t.right[1], 1271) << "(pairs listed above)";
  EXPECT_GE(t.right[2], 1242) << "(pairs listed above)";
  EXPECT_GE(t.right[3], 1279) << "(pairs listed above)";
  EXPECT_GE(t.right[4], 1278) << "(pairs listed above)";
}

namespace {

// The preset's verdict at every error of eval::sweepErrors (1, 2, 4, 8 tolerances along each
// axis both ways; 5-180 deg of yaw) on every pair:
// returns the errors accepted and the ground truths rejected, one line each.
struct SweepTally {
  int pairs = 0, errors = 0, errors_accepted = 0, truths_rejected = 0;
  int truths_rejected_flat = 0;  // of those, by the gate's flat axes (max_flat_axes)
  std::ostringstream wrong;
};
// The sweep of data set d's pairs under `judge` (the preset's stream or loop verdict), every
// `every`-th pair, errors of these multiples of the tolerance and turns of these angles about
// these axes.
void sweepPairs(const std::string& preset, const online::IntrospectorConfig& judge,
                const eval::PairDataset& d, SweepTally* t,
                const std::vector<double>& multiples = eval::sweepMultiples(),
                std::size_t every = 1,
                const std::vector<double>& yaw_degrees = eval::sweepYawDegrees(),
                const std::vector<eval::TurnAxis>& turn_axes = eval::sweepTurnAxes()) {
  const auto errors = eval::sweepErrors(judge.verdict.tolerance, judge.coral.dimension, multiples,
                                        yaw_degrees, turn_axes);
  const int pairs0 = t->pairs, errors0 = t->errors, accepted0 = t->errors_accepted,
            rejected0 = t->truths_rejected;  // earlier data sets of the same test
  // Under CORAL_VERDICT_PAIR_STRIDE (the sanitizer build, ~55x slower) one pair per data set:
  // the 58 poses of every Livox pair would take ~2 hours there.
  const std::size_t step = stride() > 1 ? d.pairs.size() : every;
  for (std::size_t i = 0; i < d.pairs.size(); i += step) {
    const eval::ScanPair& p = d.pairs[i];
    ++t->pairs;
    for (const eval::SweepError& e : errors) {
      const coral::AlignmentVerdict v =
          online::judgePair(d.scans[p.a].scan, d.scans[p.b].scan, p.T_a_b * e.delta, judge, false)
              .verdict;
      t->errors += !e.ground_truth;
      const bool accepted = v.valid && v.aligned;
      if (accepted != e.ground_truth) {
        (e.ground_truth ? t->truths_rejected : t->errors_accepted) += 1;
        t->truths_rejected_flat +=
            e.ground_truth && v.valid && v.rejected_by.find("flat axes") != std::string::npos;
        t->wrong << "  pair " << i << " " << e.label << ": " << (accepted ? "accepted" : "rejected")
                 << " (" << (v.valid ? v.rejected_by : v.reason) << "; p "
                 << v.classifier.probability << ", overlap " << v.coral.overlap << ")\n";
      }
    }
  }
  std::cout << preset << " on " << d.name << ": " << t->pairs - pairs0 << " pairs x "
            << errors.size() << " poses: errors accepted " << t->errors_accepted - accepted0
            << " / " << t->errors - errors0 << ", ground truth rejected "
            << t->truths_rejected - rejected0 << " / " << t->pairs - pairs0 << "\n"
            << t->wrong.str();
  t->wrong.str("");
}

void sweepDataSet(const std::string& preset, const std::string& spec_text, SweepTally* t,
                  const std::vector<double>& multiples = eval::sweepMultiples(),
                  std::size_t every = 1,
                  const std::vector<double>& yaw_degrees = eval::sweepYawDegrees()) {
  ros_adapters::NodeConfig node;
  eval::PairDataset d;
  if (!loadPresetData(preset, spec_text, &node, &d)) return;
  sweepPairs(preset, node.online, d, t, multiples, every, yaw_degrees);
}

// Errors between the steps of the default sweep: 1.5-10 tolerances, yaw between its fixed
// angles (and between the coarse probe's quarter and half turns).
const std::vector<double> kBetweenMultiples{1.5, 2.5, 3.0, 5.0, 6.0, 10.0};
const std::vector<double> kBetweenYawDegrees{10, 20, 30, 60, 120, 135, 150, 170};

}  // namespace

// Errors of every size (not only one tolerance), every pair: the relative check alone accepted
// errors past the CorAl radius (Oxford: y+8 in 5/10 pairs, yaw 180 deg in 10/10; Livox: yaw
// 90 deg in 79/80 pairs of every 4th); the gated preset verdict rejects each of them and keeps
// ground truth.
// Also errors between the steps 1, 2, 4, 8 (1.5-10 tolerances), yaw between the fixed angles
// (10-170 deg), and through the loop verdict:
// with gate/min_probability 0.01 the stream verdict accepted x-6 tolerances (3 m) on pair 0
// (p 0.052, x flat; doc/verdict_every_error.md).
TEST(PresetVerdicts, EveryErrorSizeRadarOxford) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  ros_adapters::NodeConfig node;
  eval::PairDataset d;
  ASSERT_TRUE(loadPresetData("radar_oxford", "oxford:" + coral_data, &node, &d));
  online::IntrospectorConfig loop = node.online;
  loop.verdict = coral::loopClosureVerdict(node.online.verdict);
  for (const online::IntrospectorConfig* judge : {&node.online, &loop})
    for (bool between : {false, true}) {
      SweepTally t;
      sweepPairs(judge == &loop ? "radar_oxford (loop verdict)" : "radar_oxford", *judge, d, &t,
                 between ? kBetweenMultiples : eval::sweepMultiples(), 1,
                 between ? kBetweenYawDegrees : eval::sweepYawDegrees());
      EXPECT_EQ(t.pairs, stride() > 1 ? 1 : 10);
      EXPECT_EQ(t.errors_accepted, 0) << "(listed above)";
      EXPECT_EQ(t.truths_rejected, 0) << "(listed above)";
    }
}

namespace {

// Verdict samples of every `every`-th pair of d, as coral_train --preset builds them for the
// preset `c`; sample.pair * every is the pair's index in d.
eval::SampleSet presetSamples(const online::IntrospectorConfig& c, const eval::PairDataset& d,
                              std::size_t every = 1) {
  eval::VerdictSampleConfig scfg;
  scfg.coral = c.coral;
  scfg.tolerance = c.verdict.tolerance;
  scfg.probe_queries = c.verdict.relative.probe_queries;
  std::vector<eval::ScanPair> pairs;
  for (std::size_t i = 0; i < d.pairs.size(); i += every) pairs.push_back(d.pairs[i]);
  eval::SampleSet samples;
  std::string err;
  EXPECT_TRUE(eval::buildVerdictSamples(d.name, d.scans, pairs, scfg, nullptr, &samples, &err))
      << err;
  return samples;
}

// The classifier coral_train --preset fits (eval::evaluateVerdicts' deployable fit) on the
// samples with finite CorAl features (eval::selectSamples) that `use` keeps.
coral::ClassifierConfig heldOutClassifier(const eval::SampleSet& samples,
                                          const std::function<bool(const eval::Sample&)>& use) {
  std::vector<int> train;
  int no_coral = 0;
  eval::selectSamples(samples, 0, "", &train, &no_coral);
  train.erase(
      std::remove_if(train.begin(), train.end(), [&](int k) { return !use(samples.samples[k]); }),
      train.end());
  coral::LogisticModel model;
  std::string err;
  EXPECT_TRUE(
      eval::fitSamples(samples, 0, train, eval::EvaluationConfig().regression, &model, &err))
      << err;
  return model.toClassifierConfig();
}

// Pair i of d swept (on and between the default steps; stream and loop verdict) with the
// preset `c` holding `classifier` instead of its own.
void sweepHeldOut(const std::string& label, const online::IntrospectorConfig& c,
                  const coral::ClassifierConfig& classifier, const eval::PairDataset& d,
                  std::size_t i, SweepTally* stream, SweepTally* loop_tally) {
  online::IntrospectorConfig held_out = c;
  held_out.verdict.classifier = classifier;
  online::IntrospectorConfig loop = held_out;
  loop.verdict = coral::loopClosureVerdict(held_out.verdict);
  const eval::ScanPair& p = d.pairs[i];
  eval::PairDataset one;  // the pair's two scans only
  one.name = d.name;
  one.scans = {d.scans[p.a], d.scans[p.b]};
  one.pairs = {{0, 1, p.T_a_b}};
  const std::string name = label + ", pair " + std::to_string(i) + " held out";
  for (bool between : {false, true}) {
    const auto& multiples = between ? kBetweenMultiples : eval::sweepMultiples();
    const auto& yaw = between ? kBetweenYawDegrees : eval::sweepYawDegrees();
    sweepPairs(name, held_out, one, stream, multiples, 1, yaw);
    sweepPairs(name + " (loop verdict)", loop, one, loop_tally, multiples, 1, yaw);
  }
}

}  // namespace

// The same sweeps with a classifier that never saw the pair judged. radar_oxford's classifier
// was trained on these 10 pairs, so the test above is in-sample for its gate. Here pair i is
// judged with the classifier coral_train --preset fits on the pairs that share no scan with it
// (|j - i| >= 2: 7-8 pairs), everything else as shipped. Measured (2026-12-06,
// doc/verdict_every_error.md): the fold classifiers put ground truth at p 0.10-1.0 and pair 0's
// x-6 tolerances (3 m along the road, which the relative check passes) at p 0.14, so the gate
// of 0.1 alone accepted it; with the coarse probe (steps to 8 tolerances) and the gate at 0.001,
// 0 of 850 errors accepted, ground truth 10 / 10.
TEST(PresetVerdicts, EveryErrorSizeRadarOxfordWithAClassifierThatNeverSawThePair) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  ros_adapters::NodeConfig node;
  eval::PairDataset d;
  ASSERT_TRUE(loadPresetData("radar_oxford", "oxford:" + coral_data, &node, &d));
  ASSERT_EQ(d.pairs.size(), 10u);
  const eval::SampleSet samples = presetSamples(node.online, d);
  SweepTally stream, loop_tally;
  for (std::size_t i = 0; i < d.pairs.size(); i += stride()) {
    const coral::ClassifierConfig fold = heldOutClassifier(samples, [i](const eval::Sample& s) {
      return std::abs(s.pair - static_cast<int>(i)) >= 2;
    });
    ASSERT_NE(fold.beta1, node.online.verdict.classifier.beta1);
    sweepHeldOut("radar_oxford", node.online, fold, d, i, &stream, &loop_tally);
  }
  for (const SweepTally* t : {&stream, &loop_tally}) {
    EXPECT_EQ(t->pairs, 2 * judged(10));  // two sweeps per pair
    EXPECT_EQ(t->errors_accepted, 0) << "(listed above)";
    EXPECT_EQ(t->truths_rejected, 0) << "(listed above)";
  }
}

// lidar_3d's classifier was trained on every Livox pair and the car pair, so the tests below are
// in-sample for its gate. Here the Livox sequence is cut into 4 contiguous blocks (a block is a
// different part of the campus); every 16th pair of a block is judged with the classifier fitted
// on the car pair and the Livox pairs outside the block (every 2nd, none within 2 pairs of it),
// on and between the default steps, stream and loop verdict. Measured (2026-12-06): 0 of 2900
// errors accepted by either verdict, ground truth 20 / 20 (77 s in Release; under
// CORAL_VERDICT_PAIR_STRIDE the samples of every 64th pair and one pair judged).
TEST(PresetVerdicts, EveryErrorSizeLidar3dWithAClassifierThatNeverSawThePair) {
  CORAL_REQUIRE_DATA("hku1_livox_keyframes");
  ros_adapters::NodeConfig node;
  eval::PairDataset livox, car;
  ASSERT_TRUE(loadPresetData("lidar_3d", "keyframes:" + coral_data, &node, &livox));
  loadData(node,
           "cloudlist:" + coral_test::dataDir() + "/libpointmatcher_car_cloud/carCloudList.csv",
           &car);
  ASSERT_FALSE(HasFatalFailure());
  const std::size_t every = stride() > 1 ? 64 : 2, n = livox.pairs.size(), blocks = 4;
  eval::SampleSet samples = presetSamples(node.online, livox, every);
  std::string err;
  ASSERT_TRUE(eval::mergeSampleSets(&samples, presetSamples(node.online, car), &err)) << err;
  // Under CORAL_VERDICT_PAIR_STRIDE: the first pair of the first block.
  const std::size_t blocks_judged = stride() > 1 ? 1 : blocks;
  const int pair_step = stride() > 1 ? static_cast<int>(n) : 16;
  SweepTally stream, loop_tally;
  for (std::size_t b = 0; b < blocks_judged; ++b) {
    const int lo = static_cast<int>(b * n / blocks), hi = static_cast<int>((b + 1) * n / blocks);
    const coral::ClassifierConfig fold = heldOutClassifier(samples, [&](const eval::Sample& s) {
      const int pair = s.pair * static_cast<int>(every);
      return s.dataset == car.name || pair < lo - 2 || pair >= hi + 2;
    });
    std::cout << "block " << b << " (pairs " << lo << "-" << hi - 1 << "): beta " << fold.beta0
              << ", " << fold.beta1 << ", " << fold.beta2 << "\n";
    for (int i = lo; i < hi; i += pair_step)
      sweepHeldOut("lidar_3d", node.online, fold, livox, static_cast<std::size_t>(i), &stream,
                   &loop_tally);
  }
  for (const SweepTally* t : {&stream, &loop_tally}) {
    std::cout << "held out: " << t->pairs / 2 << " pairs, errors accepted " << t->errors_accepted
              << " / " << t->errors << ", ground truth rejected " << t->truths_rejected << "\n";
    EXPECT_EQ(t->pairs, stride() > 1 ? 2 : 40);  // two sweeps per pair
    EXPECT_EQ(t->errors_accepted, 0) << "(listed above)";
    EXPECT_EQ(t->truths_rejected, 0) << "(listed above)";
  }
}

TEST(PresetVerdicts, EveryErrorSizeLidar3d) {
  CORAL_REQUIRE_DATA("hku1_livox_keyframes");
  SweepTally t;
  sweepDataSet("lidar_3d", "keyframes:" + coral_data, &t);
  sweepDataSet("lidar_3d",
               "cloudlist:" + coral_test::dataDir() + "/libpointmatcher_car_cloud/carCloudList.csv",
               &t);
  EXPECT_GE(t.pairs, 2);
  EXPECT_EQ(t.errors_accepted, 0) << "(listed above)";
  EXPECT_EQ(t.truths_rejected, 0) << "(listed above)";
}

// Errors between the steps 1, 2, 4, 8 (1.5-10 tolerances) and yaw between the fixed angles
// (10-170 deg), every 16th Livox pair and the car pair. Measured (coral_error_sweep --multiples
// / --yaw_deg, every 4th pair and the car pair): 0 of 6480 and 0 of 1280 accepted, ground
// truth 80 / 80.
TEST(PresetVerdicts, EveryErrorSizeLidar3dBetweenTheSteps) {
  CORAL_REQUIRE_DATA("hku1_livox_keyframes");
  SweepTally t;
  sweepDataSet("lidar_3d", "keyframes:" + coral_data, &t, kBetweenMultiples, 16,
               kBetweenYawDegrees);
  sweepDataSet("lidar_3d",
               "cloudlist:" + coral_test::dataDir() + "/libpointmatcher_car_cloud/carCloudList.csv",
               &t, kBetweenMultiples, 1, kBetweenYawDegrees);
  EXPECT_GE(t.pairs, 2);
  EXPECT_EQ(t.errors_accepted, 0) << "(listed above)";
  EXPECT_EQ(t.truths_rejected, 0) << "(listed above)";
}

// "Any rotation": turns of 5-180 deg about roll, pitch and the tilted axis (1, 1, 1) (a mount
// knocked askew, a scan handed over upside down), every 16th Livox pair and the car pair,
// through the stream verdict and the loop verdict. Measured (coral_error_sweep --turn_axes
// roll,pitch,tilted --yaw_deg 5,15,45,90,135,180, every 4th pair and the car pair, stream
// verdict): 0 of 2640 accepted, ground truth 80 / 80; most turns of 45 deg or more leave no
// overlap (no verdict), the largest classifier p of a turn with one is 0.65 (roll 5 deg, which
// the relative check rejects). The loop verdict's gate may refuse a few of these 20 consecutive
// ground truths for two flat axes among x, y, yaw (loop_closure/max_flat_axes 1,
// doc/loop_closure.md: a loop edge along a corridor is not pinned; 3 when all six axes were
// counted, 1 of all 313 since); no ground truth is rejected for anything else.
TEST(PresetVerdicts, EveryErrorSizeLidar3dAnyRotation) {
  CORAL_REQUIRE_DATA("hku1_livox_keyframes");
  const std::vector<eval::TurnAxis> axes = {eval::TurnAxis::kRoll, eval::TurnAxis::kPitch,
                                            eval::TurnAxis::kTilted};
  const std::vector<double> degrees = {5, 15, 45, 90, 135, 180};
  for (bool loop_verdict : {false, true}) {
    SweepTally t;
    for (const std::string& spec :
         {"keyframes:" + coral_data,
          "cloudlist:" + coral_test::dataDir() + "/libpointmatcher_car_cloud/carCloudList.csv"}) {
      ros_adapters::NodeConfig node;
      eval::PairDataset d;
      ASSERT_TRUE(loadPresetData("lidar_3d", spec, &node, &d)) << spec;
      online::IntrospectorConfig judge = node.online;
      if (loop_verdict) judge.verdict = coral::loopClosureVerdict(node.online.verdict);
      sweepPairs(loop_verdict ? "lidar_3d (loop verdict)" : "lidar_3d", judge, d, &t, {},
                 spec[0] == 'k' ? 16 : 1, degrees, axes);
    }
    EXPECT_GE(t.pairs, 2);
    EXPECT_EQ(t.errors, t.pairs * 33);
    EXPECT_EQ(t.errors_accepted, 0) << "(listed above)";
    EXPECT_EQ(t.truths_rejected - (loop_verdict ? t.truths_rejected_flat : 0), 0)
        << "(listed above)";
    EXPECT_LE(t.truths_rejected_flat * 5, loop_verdict ? t.pairs : 0);
  }
}

// Errors between the axes (coral_error_sweep --oblique, 2026-12-07): two translation axes at
// once (22.5, 45, 67.5 deg between them) or x / y with yaw (shares 1:1, 1:0.5, 0.5:1), 2
// tolerances, on six Livox pairs where lidar_3d without gate/coarse_registration accepted some
// (every 4th pair: 29 of 4800 errors of 2 tolerances on 16 pairs; 14 on these six). The error
// sits in a valley of Q (a lateral shift with the turn that keeps far points in place) that
// the relative check's one-axis steps climb out of; the registration from the pose follows the
// valley to the truth, a tolerance or more away, where Q is lower (doc/verdict_every_error.md
// "Errors between the axes").
TEST(PresetVerdicts, EveryErrorSizeLidar3dBetweenTheAxes) {
  CORAL_REQUIRE_DATA("hku1_livox_keyframes");
  ros_adapters::NodeConfig node;
  eval::PairDataset d;
  ASSERT_TRUE(loadPresetData("lidar_3d", "keyframes:" + coral_data, &node, &d));
  ASSERT_TRUE(node.online.verdict.gate.coarse_registration);
  online::IntrospectorConfig without = node.online;
  without.verdict.gate.coarse_registration = false;
  std::vector<eval::SweepError> errors;
  for (const eval::SweepError& e :
       eval::sweepErrors(node.online.verdict.tolerance, 3, {2.0}, {}, {}, true))
    if (e.axis_name == "oblique") errors.push_back(e);
  ASSERT_EQ(errors.size(), 60u);
  // Under CORAL_VERDICT_PAIR_STRIDE (the sanitizer build) the first pair only.
  const std::vector<std::size_t> pairs = {20, 80, 188, 196, 240, 296};
  int accepted = 0, accepted_without = 0, judged = 0;
  for (std::size_t k = 0; k < (stride() > 1 ? 1 : pairs.size()); ++k) {
    const std::size_t i = pairs[k];
    ASSERT_LT(i, d.pairs.size());
    const eval::ScanPair& p = d.pairs[i];
    for (const eval::SweepError& e : errors) {
      ++judged;
      for (const bool with : {true, false}) {
        const coral::AlignmentVerdict v =
            online::judgePair(d.scans[p.a].scan, d.scans[p.b].scan, p.T_a_b * e.delta,
                              with ? node.online : without, false)
                .verdict;
        if (!(v.valid && v.aligned)) continue;
        (with ? accepted : accepted_without) += 1;
        std::cout << "  pair " << i << " " << e.label << " accepted "
                  << (with ? "by the preset" : "without the registration") << " (p "
                  << v.classifier.probability << ")\n";
      }
    }
  }
  std::cout << "lidar_3d, oblique errors of 2 tolerances: accepted " << accepted << " / " << judged
            << " (without the registration: " << accepted_without << ")\n";
  EXPECT_EQ(accepted, 0) << "(listed above)";
  // The term is what rejects them: 14 measured without it (2 on the first pair).
  EXPECT_GE(accepted_without, stride() > 1 ? 1 : 10);
}

// Errors of exactly one tolerance between the axes, where the registration from the pose
// measures the error to about +-0.15 tolerances: with gate/ (and loop_closure/)
// coarse_min_registered_offset at 1 the registered pose was probed only when it came back a full
// tolerance away, half of the time. lidar_3d probes it from 0.8 (stream) and 0.9 (loop gate).
// On Livox pairs where that decided (coral_error_sweep --oblique --multiples 1, with and
// without --loop_closure, 2026-12-07), the 60 shapes of one tolerance: the preset accepts fewer
// than with the bound at 1, and few at all.
TEST(PresetVerdicts, OneToleranceBetweenTheAxesLidar3d) {
  CORAL_REQUIRE_DATA("hku1_livox_keyframes");
  ros_adapters::NodeConfig node;
  eval::PairDataset d;
  ASSERT_TRUE(loadPresetData("lidar_3d", "keyframes:" + coral_data, &node, &d));
  std::vector<eval::SweepError> errors;
  for (const eval::SweepError& e :
       eval::sweepErrors(node.online.verdict.tolerance, 3, {1.0}, {}, {}, true))
    if (e.axis_name == "oblique") errors.push_back(e);
  ASSERT_EQ(errors.size(), 60u);
  for (const bool loop : {false, true}) {
    online::IntrospectorConfig preset = node.online;
    if (loop) preset.verdict = coral::loopClosureVerdict(node.online.verdict);
    ASSERT_TRUE(preset.verdict.gate.coarse_registration);
    ASSERT_LT(preset.verdict.gate.coarse_min_registered_offset, 1.0);
    online::IntrospectorConfig at_one = preset;
    at_one.verdict.gate.coarse_min_registered_offset = 1.0;
    const std::vector<std::size_t> pairs = loop ? std::vector<std::size_t>{48, 192, 208, 240}
                                                : std::vector<std::size_t>{12, 68, 84, 168};
    int accepted = 0, accepted_at_one = 0, judged = 0;
    for (std::size_t k = 0; k < (stride() > 1 ? 1 : pairs.size()); ++k) {
      ASSERT_LT(pairs[k], d.pairs.size());
      const eval::ScanPair& p = d.pairs[pairs[k]];
      for (const eval::SweepError& e : errors) {
        ++judged;
        for (const bool with : {true, false}) {
          const coral::AlignmentVerdict v =
              online::judgePair(d.scans[p.a].scan, d.scans[p.b].scan, p.T_a_b * e.delta,
                                with ? preset : at_one, false)
                  .verdict;
          if (v.valid && v.aligned) (with ? accepted : accepted_at_one) += 1;
        }
      }
    }
    std::cout << "lidar_3d " << (loop ? "loop" : "stream")
              << " verdict, one tolerance between the axes: accepted " << accepted << " / "
              << judged << " (bound at 1: " << accepted_at_one << ")\n";
    if (stride() > 1) continue;
    EXPECT_LE(accepted * 40, judged);  // <= 2.5 %
    EXPECT_GE(accepted_at_one, accepted + 8);
  }
}

// 64-beam automotive scans (Velodyne HDL-64 of the View-of-Delft frames), which no shared pair
// is: each frame split into two scans at the identity, swept with the stream verdict and the
// loop verdict of lidar_3d. Not a real pair (one sweep, no motion), but every error is an error
// of a real 64-beam street scene. Two splits:
// - alternate points: the two scans sample the same surfaces, so ground truth is easier than
//   between two sweeps (p > 0.9999);
// - alternate elevation bands of 0.4 deg (about one ring each: HDL-64 rings are 0.33-0.5 deg
//   apart): the two scans sample different rings, as two sweeps of a moving scanner see the
//   ground at different ranges (2026-12-06). p > 0.9999 at ground truth too; with bands of
//   0.6 / 0.8 / 1.0 / 1.5 deg (two to four rings, harsher than a real pair: ground stripes metres
//   wide that the other scan never sees) Q at the truth rises to 0.10 / 0.11 / 0.14 / 0.18 and
//   a stream gate of p >= 0.05 alone rejects 0 / 0 / 1 / 2 of the 3 frames
//   (doc/verdict_every_error.md); the 1 deg split is swept too: since the coarse probe judges
//   the band 0.001 <= p < 0.05 (gate/coarse_below_probability), its frame 01201 (p 0.017) is
//   accepted, and 0 of 252 errors;
// - alternate points with b thinned to every 8th (10-12k points against 84-97k: a sparse scan
//   against a dense one, as a 16-beam scan or a keyframe against a submap): p > 0.9999 at
//   ground truth (and at 1/16: Q 0.058-0.084).
// Measured: 0 of 57 errors accepted per frame, split and verdict; with the turns about roll,
// pitch and the tilted axis (2026-12-06) 0 of 84.
TEST(PresetVerdicts, EveryErrorSizeLidar3dOnSplitHdl64Scans) {
  CORAL_REQUIRE_DATA("view_of_delft_example/lidar/training/velodyne");
  ros_adapters::NodeConfig node;
  coral_test::loadPreset("lidar_3d", &node);
  const std::size_t frames = stride() > 1 ? 1 : 3;
  enum Split { kAlternatePoints, kRings, kSparseB, kWideRings };
  const char* names[] = {"alternate points", "0.4 deg elevation bands",
                         "alternate points, b thinned to every 8th", "1 deg elevation bands"};
  // Under the sanitizers' stride one split only (the same code runs for each; 497 s of ASan
  // for this test file with all three).
  std::vector<Split> splits = {kAlternatePoints, kRings, kSparseB, kWideRings};
  if (stride() > 1) splits = {kRings};
  std::vector<eval::LoadedCloud> clouds;  // read once, split four ways
  for (const char* frame : {"00549", "01047", "01201"}) {
    if (clouds.size() == frames) break;
    clouds.emplace_back();
    std::string err;
    ASSERT_TRUE(eval::loadCloud(coral_data + "/" + frame + ".bin", &clouds.back(), &err)) << err;
    ASSERT_GT(clouds.back().points.size(), 100000u) << frame;
  }
  for (const Split split : splits) {
    eval::PairDataset d;
    d.name = std::string("View-of-Delft HDL-64 frames split by ") + names[split];
    const double band_deg = split == kRings ? 0.4 : split == kWideRings ? 1.0 : 0.0;
    for (const eval::LoadedCloud& c : clouds) {
      eval::TrainingScan halves[2];
      for (std::size_t i = 0; i < c.points.size(); ++i) {
        const coral::Vec3& p = c.points[i];
        const double elevation_deg = std::atan2(p.z(), p.head<2>().norm()) * 180.0 / M_PI;
        const long half = band_deg > 0.0 ? static_cast<long>(std::floor(elevation_deg / band_deg))
                                         : static_cast<long>(i);
        if (split == kSparseB && (half & 1) && i % 16 != 1) continue;  // every 8th of b's
        halves[half & 1].scan.points.push_back(p);
      }
      ASSERT_GT(halves[0].scan.points.size(), 40000u);
      ASSERT_GT(halves[1].scan.points.size(), split == kSparseB ? 8000u : 40000u);
      d.pairs.push_back({static_cast<int>(d.scans.size()), static_cast<int>(d.scans.size()) + 1,
                         Eigen::Isometry3d::Identity()});
      d.scans.push_back(halves[0]);
      d.scans.push_back(halves[1]);
    }
    online::IntrospectorConfig loop = node.online;
    loop.verdict = coral::loopClosureVerdict(node.online.verdict);
    for (const online::IntrospectorConfig* judge : {&node.online, &loop}) {
      SweepTally t;
      // The fixed angles about every turn axis (roll, pitch and tilted too: "any rotation").
      sweepPairs(judge == &loop ? "lidar_3d (loop verdict)" : "lidar_3d", *judge, d, &t,
                 eval::sweepMultiples(), 1, eval::sweepYawDegrees(),
                 {eval::TurnAxis::kYaw, eval::TurnAxis::kRoll, eval::TurnAxis::kPitch,
                  eval::TurnAxis::kTilted});
      EXPECT_EQ(t.pairs, static_cast<int>(frames)) << d.name;
      EXPECT_EQ(t.errors, t.pairs * (48 + 4 * 9)) << d.name;
      EXPECT_EQ(t.errors_accepted, 0) << d.name << " (listed above)";
      EXPECT_EQ(t.truths_rejected, 0) << d.name << " (listed above)";
    }
  }
}

// ACES corridors: an error along the corridor cannot be seen (flat axis, doc/verdict_pairs.md),
// so some errors are accepted at any size; the gate removes most of what the relative check
// alone accepts. Measured on every pair (coral_error_sweep, doc/verdict_every_error.md):
// relative check and classifier gate 684 of 42207 errors accepted, 31 of 1279 ground truths
// rejected (29 by the relative check); with the coarse probe (lidar_2d's gate: steps of 2, 4, (6,)
// 8 tolerances, turns, the registration from the pose) 74 accepted (70 along an axis the check
// reports flat, 49 of them one tolerance along x), 34 ground truths rejected; with the overlap
// bound (gate/min_overlap 0.25, 2026-12-05) 70 accepted, 36 rejected (two loop relations whose
// scans overlap by 0.09 and 0.11); with the free-space bound (gate/max_free_space 0.08,
// 2026-12-05) 68 accepted, 38 rejected (pairs 405 and 1268, conflicts 0.094 and 0.151); with
// the constraint bound (gate/min_constraint 0.04, 2026-12-05) 58 accepted, 41 rejected (794,
// 953, 1270: constraint 0.014-0.038).
TEST(PresetVerdicts, EveryErrorSizeLidar2dAces) {
  CORAL_REQUIRE_DATA("radish_aces");
  SweepTally t;
  sweepDataSet("lidar_2d", "carmen:" + coral_data + "/aces.clf.bz2", &t);
  EXPECT_LE(t.errors_accepted, stride() > 1 ? t.errors : 58) << "(listed above)";
  EXPECT_LE(t.truths_rejected, stride() > 1 ? t.pairs : 41) << "(listed above)";
}

// Errors between the sweep's steps (1.5, 2.5, 3, 5, 6, 10 tolerances), where a step of powers
// of two lands off the narrow minimum of Q at the truth: the registration from the pose and
// the steps two tolerances apart (6 since 2026-12-05) are what catch them. Every 4th ACES
// relation. Measured (coral_error_sweep --multiples, every even relation): 514 of 28800 errors
// accepted without the coarse probe, 300 with the steps 2, 4, 8 alone, 106 with the
// registration, 55 with the steps 2, 4, 6, 8, 41 with the overlap bound too, 29 with the
// free-space bound too, 24 with the constraint bound too (the preset); on every 4th relation
// as below: 49 -> 25 -> 19 -> 11 -> 10 of 14400 accepted, 10 of 320 ground truths rejected (11
// since the free-space bound: pair 1268).
TEST(PresetVerdicts, EveryErrorSizeLidar2dAcesBetweenTheProbeSteps) {
  CORAL_REQUIRE_DATA("radish_aces");
  SweepTally t;
  sweepDataSet("lidar_2d", "carmen:" + coral_data + "/aces.clf.bz2", &t,
               {1.5, 2.5, 3.0, 5.0, 6.0, 10.0}, 4);
  EXPECT_LE(t.errors_accepted, stride() > 1 ? t.errors : 10) << "(listed above)";
  EXPECT_LE(t.truths_rejected, stride() > 1 ? t.pairs : 11) << "(listed above)";
}
