// Cross-validation over contiguous pair blocks, train/test, and the report writers.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "coral_introspection/eval/evaluation.hpp"
#include "coral_introspection/eval/training_report.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::eval;

namespace {
// 10 pairs, 1 aligned + 2 misaligned samples per pair and group. In pairs 0-4 aligned has
// x = 0 and misaligned x = 1; in pairs 5-9 it is the other way round. A classifier trained
// on one half is exactly wrong on the other: held-out 2-fold CV over contiguous blocks
// must score 0, while any leak of a test pair into training would lift it.
SampleSet flippedHalves() {
  SampleSet set;
  set.methods = {{"M", {"x"}}};
  set.groups = {"0.3 m"};
  std::mt19937 rng(1);
  std::normal_distribution<double> g(0.0, 0.05);
  for (int p = 0; p < 10; ++p) {
    const double al = p < 5 ? 0.0 : 1.0;
    Sample s;
    s.pair = p;
    s.features = {{al + g(rng)}};
    set.samples.push_back(s);
    for (const char* name : {"forward", "left"}) {
      Sample m = s;
      m.offset = name;
      m.group = "0.3 m";
      m.label = 0;
      m.features = {{1.0 - al + g(rng)}};
      set.samples.push_back(m);
    }
  }
  return set;
}
}  // namespace

TEST(Evaluation, ContiguousFoldsNeverPredictInSample) {
  EvaluationConfig cfg;
  cfg.folds = 2;
  std::vector<EvaluationRow> rows;
  std::string err;
  ASSERT_TRUE(crossValidate(flippedHalves(), cfg, &rows, &err)) << err;
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].folds, 2);
  EXPECT_EQ(rows[0].pairs, 10);
  EXPECT_EQ(rows[0].aligned, 10);
  EXPECT_EQ(rows[0].misaligned, 20);
  EXPECT_DOUBLE_EQ(rows[0].accuracy, 0.0);
  EXPECT_DOUBLE_EQ(rows[0].auc, 0.0);
}

TEST(Evaluation, SeparableDataScoresPerfectlyAndGroupsSelectMisalignedSamples) {
  SampleSet set = flippedHalves();
  set.groups = {"0.3 m", "0.7 m"};
  for (Sample& s : set.samples) {
    s.features[0][0] = s.label ? 0.1 * s.pair : 5.0 + 0.1 * s.pair;  // separable everywhere
    if (s.offset == "left") s.group = "0.7 m";
  }
  set.samples[5].features[0][0] = NAN;  // a failed method value is skipped, not scored
  std::vector<EvaluationRow> rows;
  std::string err;
  ASSERT_TRUE(crossValidate(set, EvaluationConfig(), &rows, &err)) << err;
  ASSERT_EQ(rows.size(), 2u);
  for (const EvaluationRow& r : rows) {
    EXPECT_EQ(r.folds, 5);
    EXPECT_DOUBLE_EQ(r.accuracy, 1.0) << r.group;
    EXPECT_DOUBLE_EQ(r.auc, 1.0);
    EXPECT_EQ(r.aligned, 10);
  }
  // Sample 5 is pair 1's "left" sample: only the 0.7 m row loses it.
  EXPECT_EQ(rows[0].misaligned, 10);
  EXPECT_EQ(rows[1].misaligned, 9);
  EXPECT_EQ(rows[1].skipped, 1);
}

TEST(Evaluation, TrainOnOneSetTestOnAnother) {
  const SampleSet all = flippedHalves();
  SampleSet a = all, b = all;
  a.samples.assign(all.samples.begin(), all.samples.begin() + 15);  // pairs 0-4
  b.samples.assign(all.samples.begin() + 15, all.samples.end());    // pairs 5-9
  std::vector<EvaluationRow> rows;
  std::string err;
  ASSERT_TRUE(trainTest(a, a, EvaluationConfig(), &rows, &err)) << err;
  EXPECT_DOUBLE_EQ(rows[0].accuracy, 1.0);
  ASSERT_TRUE(trainTest(a, b, EvaluationConfig(), &rows, &err)) << err;
  EXPECT_DOUBLE_EQ(rows[0].accuracy, 0.0);  // the generalization failure is reported
  EXPECT_EQ(rows[0].pairs, 5);
}

TEST(TrainingReport, ClassifierYamlHasTheNodeletParameterNames) {
  ClassifierConfig c;
  c.beta0 = 1.5;
  c.beta1 = -20.25;
  c.beta2 = 19.75;
  c.threshold = 0.5;
  EXPECT_EQ(classifierYaml(c, {"trained by test"}),
            "# trained by test\nclassifier:\n  method: classifier\n  beta0: 1.5\n  beta1: -20.25\n "
            " beta2: 19.75\n"
            "  threshold: 0.5\n");
}

TEST(TrainingReport, CsvMarkdownAndRocPng) {
  const SampleSet set = flippedHalves();
  const std::string dir = ::testing::TempDir();
  std::string err;
  ASSERT_TRUE(writeSamplesCsv(dir + "/s.csv", set, &err)) << err;
  std::ifstream f(dir + "/s.csv");
  std::string header, first;
  std::getline(f, header);
  std::getline(f, first);
  EXPECT_EQ(header, "pair,stamp_a,stamp_b,offset,dx,dy,dyaw,group,label,M/x");
  EXPECT_EQ(first.substr(0, 36), "0,0.000000,0.000000,aligned,0,0,0,,1");
  std::vector<EvaluationRow> rows;
  EvaluationConfig cfg;
  cfg.folds = 2;
  ASSERT_TRUE(crossValidate(set, cfg, &rows, &err));
  const std::string md = markdownTables(rows, set.groups);
  EXPECT_NE(md.find("| M | 0.00/0.00 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| M | 0.3 m | 0.00 | 0.00 | 0.00 | 10 | 10 | 20 | 0 | 2 |"), std::string::npos)
      << md;
  ASSERT_TRUE(writeRocPng(dir + "/roc.png", rows, set.groups, &err)) << err;
  const cv::Mat img = cv::imread(dir + "/roc.png");
  ASSERT_FALSE(img.empty());
  EXPECT_EQ(img.cols, 430);
}
