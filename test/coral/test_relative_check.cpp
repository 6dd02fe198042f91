// Tolerance offsets, the relative check's decision on known Q landscapes, and the full
// relative check / verdict on a ray-cast scene with induced misalignments.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "coral_introspection/coral/types.hpp"
#include "coral_introspection/coral/verdict.hpp"
#include "coral_introspection/eval/synthetic.hpp"
#include "support/yard_pair.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::eval;

TEST(Tolerance, OffsetsPerDimensionWithSizesAndNames) {
  ToleranceConfig tol;
  tol.translation = 0.4;
  tol.rotation_deg = 3.0;
  const std::vector<ToleranceOffset> o2 = toleranceOffsets(tol, 2);
  ASSERT_EQ(o2.size(), 6u);
  const char* names[] = {"x+", "x-", "y+", "y-", "yaw+", "yaw-"};
  for (int i = 0; i < 6; ++i) EXPECT_EQ(o2[i].name, names[i]);
  EXPECT_TRUE(o2[1].delta.translation().isApprox(Eigen::Vector3d(-0.4, 0, 0)));
  EXPECT_TRUE(o2[1].delta.linear().isIdentity());
  EXPECT_NEAR(yawOf(o2[4].delta.linear()), 3.0 * M_PI / 180, 1e-12);
  EXPECT_TRUE(o2[4].delta.translation().isZero());
  const std::vector<ToleranceOffset> o3 = toleranceOffsets(tol, 3);
  ASSERT_EQ(o3.size(), 12u);
  EXPECT_EQ(o3[4].name, "z+");
  EXPECT_NEAR(o3[4].delta.translation().z(), 0.4, 1e-12);
  EXPECT_EQ(o3[6].name, "roll+");  // about x: y goes to z
  EXPECT_NEAR((o3[6].delta.linear() * Eigen::Vector3d::UnitY()).z(), std::sin(3.0 * M_PI / 180),
              1e-12);
  EXPECT_EQ(ToleranceConfig::forSensor(true, 2).translation, 0.5);
  EXPECT_EQ(ToleranceConfig::forSensor(false, 2).rotation_deg, 5.0);
  tol.translation = 0.0;
  EXPECT_NE(tol.validate().find("translation"), std::string::npos);
}

// probe_queries: 0 (every query) or enough for the relative check (kMinProbeQueries: fewer
// changed its decisions on real pairs and judged ground truth misaligned, doc/coral_core.md).
TEST(RelativeCheckConfig, ProbeQueriesZeroOrAtLeastTheMinimum) {
  RelativeCheckConfig c;
  for (int ok : {0, RelativeCheckConfig::kMinProbeQueries, 250, 100000}) {
    c.probe_queries = ok;
    EXPECT_EQ(c.validate(), "") << ok;
  }
  for (int bad : {-1, 1, 2, RelativeCheckConfig::kMinProbeQueries - 1}) {
    c.probe_queries = bad;
    EXPECT_EQ(c.validate(),
              "probe_queries must be 0 (every CorAl query) or >= 50: fewer change "
              "the relative check's decisions on real pairs and judge ground truth "
              "misaligned (doc/coral_core.md) (got " +
                  std::to_string(bad) + ")");
  }
}

namespace {
// Q of a quadratic bowl c_x dx^2 + c_y dy^2 + c_yaw dyaw^2 (tolerance units) around `truth`,
// seen from a pose at `at`: the neighbours are at + each offset.
std::vector<double> bowl(const Eigen::Vector3d& at, const Eigen::Vector3d& c,
                         const std::vector<ToleranceOffset>& offsets, double* q0) {
  auto q = [&](const Eigen::Vector3d& d) { return 0.2 + c.dot(d.cwiseAbs2()); };
  *q0 = q(at);
  std::vector<double> out;
  for (const ToleranceOffset& o : offsets) {
    Eigen::Vector3d d = at;
    d[o.axis == Axis::kYaw ? 2 : static_cast<int>(o.axis)] += o.sign;
    out.push_back(q(d));
  }
  return out;
}
// Q at the pose and at its neighbours first, then the decision: in one call expression
// decideRelative(q0, off, bowl(..., &q0), cfg) the order in which the arguments are
// evaluated is unspecified (gcc and clang differ), so q0 could be read before bowl sets it.
RelativeCheckResult decideBowl(const Eigen::Vector3d& at, const Eigen::Vector3d& c,
                               const std::vector<ToleranceOffset>& offsets,
                               const RelativeCheckConfig& cfg) {
  double q0 = 0.0;
  const std::vector<double> neighbours = bowl(at, c, offsets, &q0);
  return decideRelative(q0, offsets, neighbours, cfg);
}
}  // namespace

TEST(RelativeCheck, DecisionOnAKnownBowl) {
  const std::vector<ToleranceOffset> off = toleranceOffsets(ToleranceConfig(), 2);
  RelativeCheckConfig cfg;
  double q0 = 0.0;
  // At the minimum every neighbour is higher (by c_k): aligned, no hint, s_k = -1 each.
  const Eigen::Vector3d c(1.0, 0.5, 0.8);
  RelativeCheckResult r = decideBowl({0, 0, 0}, c, off, cfg);
  ASSERT_TRUE(r.valid);
  EXPECT_FALSE(r.misaligned);
  EXPECT_TRUE(r.hint.name.empty());
  EXPECT_NEAR(r.scale, 1.0, 1e-12);
  EXPECT_NEAR(r.score, -1.0, 1e-12);
  EXPECT_NEAR(r.axes[1].sensitivity, 0.5, 1e-12);
  EXPECT_TRUE(r.flat_axes.empty());
  // One tolerance off along +x: the step x- reaches the truth (Q drops by D = c_x = 1, the
  // step x+ raises it by U = 3): s_x = 2D / (D + U) = 0.5.
  r = decideBowl({1, 0, 0}, c, off, cfg);
  EXPECT_TRUE(r.misaligned);
  EXPECT_EQ(r.hint.name, "x-");
  EXPECT_NEAR(r.q, 1.2, 1e-12);
  EXPECT_NEAR(r.scale, 2.0, 1e-12);
  EXPECT_NEAR(r.score, 0.5, 1e-12);
  EXPECT_NEAR(r.axes[1].score, -1.0, 1e-12);
  // Off along yaw the other way round.
  r = decideBowl({0, 0, -1}, c, off, cfg);
  EXPECT_TRUE(r.misaligned);
  EXPECT_EQ(r.hint.name, "yaw+");
  // A corridor: Q barely changes along y. Without noise the slope still shows (s_y = 0.5),
  // and y is reported flat: on real data such an axis decides unreliably.
  const Eigen::Vector3d corridor(1.0, 0.001, 0.8);
  r = decideBowl({0, 1, 0}, corridor, off, cfg);
  EXPECT_TRUE(r.misaligned);
  EXPECT_EQ(r.hint.name, "y-");
  ASSERT_EQ(r.flat_axes.size(), 1u);
  EXPECT_EQ(r.flat_axes[0], Axis::kY);
  // A larger margin tolerates a smaller asymmetry: s_x = 0.5 passes a margin of 0.6.
  cfg.margin = 0.6;
  EXPECT_FALSE(decideBowl({1, 0, 0}, c, off, cfg).misaligned);
  cfg.margin = 0.2;
  // Missing neighbours: the axis with values still decides; none at all is invalid.
  std::vector<double> q = bowl({1, 0, 0}, c, off, &q0);
  q[2] = q[3] = std::nan("");
  r = decideRelative(q0, off, q, cfg);
  EXPECT_TRUE(r.valid);
  EXPECT_FALSE(r.axes[1].valid);
  EXPECT_TRUE(r.misaligned);
  r = decideRelative(q0, off, std::vector<double>(6, std::nan("")), cfg);
  EXPECT_FALSE(r.valid);
  EXPECT_FALSE(r.misaligned);
}

// The flat-axes bound counts x, y and yaw only: a narrow-FOV lidar's y and roll are flat at
// true poses (45 of 313 consecutive Livox ground truths), a look-alike turned onto another
// place has two of x, y, yaw flat.
TEST(RelativeCheck, TheGateCountsFlatAxesAmongXYAndYaw) {
  EXPECT_EQ(horizontalFlatAxes({Axis::kY, Axis::kRoll}), std::vector<Axis>({Axis::kY}));
  EXPECT_EQ(horizontalFlatAxes({Axis::kY, Axis::kRoll, Axis::kYaw}),
            std::vector<Axis>({Axis::kY, Axis::kYaw}));
  EXPECT_EQ(horizontalFlatAxes({Axis::kX, Axis::kZ, Axis::kRoll, Axis::kPitch, Axis::kYaw}),
            std::vector<Axis>({Axis::kX, Axis::kYaw}));
  EXPECT_TRUE(horizontalFlatAxes({Axis::kZ, Axis::kRoll, Axis::kPitch}).empty());
}

using coral_introspection::test::planarYardCoral;
using coral_introspection::test::yardPair;
using Pair = coral_introspection::test::YardPair;

TEST(RelativeCheck, PlanarScanPairAtTruthAndOneToleranceOff) {
  const Pair p = yardPair(1);
  const CoralConfig coral = planarYardCoral();
  VerdictConfig v;
  v.method = VerdictMethod::kRelative;
  v.tolerance = ToleranceConfig::lidar2d();
  AlignmentVerdict at_truth = judgeAlignment(p.a, p.b, p.T_a_b, coral, v);
  ASSERT_TRUE(at_truth.valid) << at_truth.reason;
  EXPECT_TRUE(at_truth.aligned) << "score " << at_truth.relative.score;
  EXPECT_EQ(at_truth.relative.coral_evaluations, 6);
  EXPECT_GT(at_truth.probability, 0.5);
  for (const ToleranceOffset& o : toleranceOffsets(v.tolerance, 2)) {
    const AlignmentVerdict off = judgeAlignment(p.a, p.b, p.T_a_b * o.delta, coral, v);
    ASSERT_TRUE(off.valid) << o.name;
    EXPECT_FALSE(off.aligned) << o.name << " score " << off.relative.score;
    std::string back = o.name;
    back.back() = back.back() == '+' ? '-' : '+';
    EXPECT_EQ(off.relative.hint.name, back) << o.name;
    EXPECT_LT(off.probability, 0.5) << o.name;
  }
}

TEST(Verdict, MethodsCombineClassifierAndRelativeCheck) {
  const Pair p = yardPair(1);
  const CoralConfig coral = planarYardCoral();
  VerdictConfig v;
  v.tolerance = ToleranceConfig::lidar2d();
  v.classifier.beta0 = 100.0;  // a classifier that calls everything aligned
  v.classifier.beta1 = v.classifier.beta2 = 0.0;
  const Eigen::Isometry3d off = p.T_a_b * se2(0.3, 0.0, 0.0);
  v.method = VerdictMethod::kClassifier;
  AlignmentVerdict r = judgeAlignment(p.a, p.b, off, coral, v);
  EXPECT_TRUE(r.aligned);
  EXPECT_FALSE(r.relative.valid);  // not computed for the classifier alone
  v.method = VerdictMethod::kBoth;
  r = judgeAlignment(p.a, p.b, off, coral, v);
  EXPECT_TRUE(r.valid);
  EXPECT_FALSE(r.aligned);  // the relative check vetoes
  EXPECT_NEAR(r.probability, relativeProbability(r.relative, v.relative), 1e-12);
  VerdictMethod m;
  EXPECT_TRUE(parseVerdictMethod("both", &m));
  EXPECT_EQ(m, VerdictMethod::kBoth);
  EXPECT_FALSE(parseVerdictMethod("Both", &m));
  // No overlap: no verdict, and the neighbours are not evaluated.
  r = judgeAlignment(p.a, p.b, se2(500.0, 0.0, 0.0), coral, v);
  EXPECT_FALSE(r.valid);
  EXPECT_FALSE(r.aligned);
  EXPECT_EQ(r.relative.coral_evaluations, 0);
  EXPECT_FALSE(r.reason.empty());
}

// The gated verdict: the relative check, then the absolute gate (classifier p, overlap). At
// ground truth a gate the pair passes keeps it aligned; the same pose with a gate above the
// pair's p, or above its overlap, is rejected and says which term did it; an offset the
// relative check flags is rejected by the relative check whatever the gate says.
TEST(Verdict, GatedRejectsWhatTheGateRejectsAndNamesTheTerm) {
  const Pair p = yardPair(1);
  const CoralConfig coral = planarYardCoral();
  VerdictConfig v;
  v.tolerance = ToleranceConfig::lidar2d();
  v.method = VerdictMethod::kGated;
  AlignmentVerdict r = judgeAlignment(p.a, p.b, p.T_a_b, coral, v);  // gate off (defaults)
  ASSERT_TRUE(r.valid) << r.reason;
  ASSERT_TRUE(r.aligned) << r.rejected_by;
  EXPECT_TRUE(r.rejected_by.empty());
  const double p_gt = r.classifier.probability, overlap_gt = r.coral.overlap;
  ASSERT_GT(p_gt, 0.0);
  ASSERT_LT(p_gt, 1.0);
  v.gate.min_probability = std::nextafter(p_gt, 0.0);  // just below: passes
  v.gate.min_overlap = std::nextafter(overlap_gt, 0.0);
  EXPECT_TRUE(judgeAlignment(p.a, p.b, p.T_a_b, coral, v).aligned);
  v.gate.min_probability = std::min(0.999, p_gt * 1.01 + 1e-9);  // above the pair's p
  r = judgeAlignment(p.a, p.b, p.T_a_b, coral, v);
  EXPECT_TRUE(r.valid);
  EXPECT_FALSE(r.aligned);
  EXPECT_NE(r.rejected_by.find("classifier p"), std::string::npos) << r.rejected_by;
  EXPECT_LE(r.probability, p_gt);
  v.gate.min_probability = 0.0;
  v.gate.min_overlap = std::min(0.999, overlap_gt + 0.01);
  r = judgeAlignment(p.a, p.b, p.T_a_b, coral, v);
  EXPECT_FALSE(r.aligned);
  EXPECT_NE(r.rejected_by.find("overlap"), std::string::npos) << r.rejected_by;
  v.gate.min_overlap = 0.0;
  // max_quality: Q at the pose exactly at the bound passes, just above it is rejected.
  const double q_gt = r.coral.quality;
  v.gate.max_quality = q_gt;
  EXPECT_TRUE(judgeAlignment(p.a, p.b, p.T_a_b, coral, v).aligned);
  v.gate.max_quality = std::nextafter(q_gt, -1e9);
  r = judgeAlignment(p.a, p.b, p.T_a_b, coral, v);
  EXPECT_TRUE(r.valid);
  EXPECT_FALSE(r.aligned);
  EXPECT_NE(r.rejected_by.find("gate: Q"), std::string::npos) << r.rejected_by;
  v.gate.max_quality = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(v.validate().find("max_quality"), std::string::npos);
  v.gate.max_quality = std::numeric_limits<double>::infinity();
  // max_flat_axes: with flat_ratio 0.99 every axis but the most sensitive one counts as flat
  // at ground truth; the bound at that count passes, one below it rejects and names them.
  v.relative.flat_ratio = 0.99;
  r = judgeAlignment(p.a, p.b, p.T_a_b, coral, v);
  ASSERT_TRUE(r.aligned) << r.rejected_by;
  const int n_flat = static_cast<int>(r.relative.flat_axes.size());
  ASSERT_EQ(n_flat, 2);
  v.gate.max_flat_axes = n_flat;
  EXPECT_TRUE(judgeAlignment(p.a, p.b, p.T_a_b, coral, v).aligned);
  v.gate.max_flat_axes = n_flat - 1;
  r = judgeAlignment(p.a, p.b, p.T_a_b, coral, v);
  EXPECT_TRUE(r.valid);
  EXPECT_FALSE(r.aligned);
  EXPECT_NE(r.rejected_by.find("gate: 2 flat axes ("), std::string::npos) << r.rejected_by;
  v.gate.max_flat_axes = -2;
  EXPECT_NE(v.validate().find("max_flat_axes"), std::string::npos);
  v.gate.max_flat_axes = 3;  // of x, y, yaw: would never reject
  EXPECT_NE(v.validate().find("max_flat_axes"), std::string::npos);
  v.gate.max_flat_axes = -1;  // off: flat axes are only reported
  EXPECT_TRUE(judgeAlignment(p.a, p.b, p.T_a_b, coral, v).aligned);
  v.relative.flat_ratio = RelativeCheckConfig().flat_ratio;
  r = judgeAlignment(p.a, p.b, p.T_a_b * se2(0.3, 0.0, 0.0), coral, v);
  EXPECT_FALSE(r.aligned);
  EXPECT_NE(r.rejected_by.find("relative check"), std::string::npos) << r.rejected_by;
  // The loop-closure verdict is the gated one with the loop gate.
  v.method = VerdictMethod::kRelative;
  v.loop_closure.min_probability = std::min(0.999, p_gt * 1.01 + 1e-9);
  const VerdictConfig loop = loopClosureVerdict(v);
  EXPECT_EQ(loop.method, VerdictMethod::kGated);
  EXPECT_EQ(loop.gate.min_probability, v.loop_closure.min_probability);
  EXPECT_TRUE(judgeAlignment(p.a, p.b, p.T_a_b, coral, v).aligned);
  EXPECT_FALSE(judgeAlignment(p.a, p.b, p.T_a_b, coral, loop).aligned);
  VerdictMethod m;
  EXPECT_TRUE(parseVerdictMethod("gated", &m));
  EXPECT_EQ(m, VerdictMethod::kGated);
  // Values outside [0, 1) are refused and named.
  v.gate.min_probability = 1.0;
  EXPECT_NE(v.validate().find("min_probability"), std::string::npos);
  v.gate.min_probability = 0.0;
  v.loop_closure.min_overlap = -0.1;
  EXPECT_NE(v.validate().find("loop_closure"), std::string::npos);
}
