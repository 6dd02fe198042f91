// CorAl for dense clouds: the subset estimator (queries from a stratified subset, full-cloud
// neighbourhoods), its standard error, the query search against brute force with fixed and
// dynamic radius, and results that do not depend on the thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <tuple>

#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/eval/synthetic.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::eval;

namespace {

struct Pair {
  Scan a, b;
};

// Two simulated 32-ring scans of the yard, b displaced by `offset` m (0 = aligned).
Pair yardPair(unsigned seed, double offset) {
  std::mt19937 rng(seed);
  const SyntheticScene scene = SyntheticScene::structuredYard();
  const LidarModel lidar;
  const Eigen::Isometry3d T_w_a = se2(0, 0, 0), T_w_b = se2(0.8, 0.3, 0.05);
  Scan a, b;
  a.points = simulateScan(scene, T_w_a, lidar, rng);
  b.points = simulateScan(scene, T_w_b, lidar, rng);
  Pair p;
  p.a = transformScan(a, T_w_a);
  p.b = transformScan(b, T_w_b * se2(offset, 0.0, 0.0));
  return p;
}

CoralConfig baseConfig() {
  CoralConfig c;
  c.radius = 0.5;
  c.epsilon = 1e-8;
  return c;
}

// Brute-force entropies of the point at `p` (of scan `scan`): every point of its own / the
// other cloud within r, moments centred on p as in the kernel.
PointEntropy bruteForce(const Pair& pr, const Vec3& p, int scan, double r, const CoralConfig& cfg) {
  Moments own, other;
  for (int s = 0; s < 2; ++s)
    for (const Vec3& x : s == 0 ? pr.a.points : pr.b.points)
      if ((x - p).norm() <= r) (s == scan ? own : other).add(x - p);
  PointEntropy pe;
  scorePoint(own, other, cfg, &pe);
  return pe;
}

// Finds the input point whose float cast equals the scored position.
Vec3 inputPoint(const Pair& pr, const PointEntropy& pe) {
  for (const Vec3& x : pe.scan == 0 ? pr.a.points : pr.b.points)
    if (x.cast<float>() == pe.position) return x;
  ADD_FAILURE() << "scored point is not an input point";
  return Vec3::Zero();
}

}  // namespace

TEST(CoralSubset, QueriesUseFullCloudNeighbourhoodsLikeBruteForce) {
  const Pair pr = yardPair(21, 0.0);
  for (bool dynamic : {false, true}) {
    CoralConfig cfg = baseConfig();
    cfg.dynamic_radius = dynamic;
    cfg.r_min = 0.2;
    cfg.r_max = 0.8;
    cfg.alpha_deg = 2.0;
    cfg.max_queries = 300;
    const CoralResult r = computeCoral(pr.a, pr.b, cfg);
    ASSERT_EQ(r.num_queries, 600u);
    ASSERT_EQ(r.per_point.size(), 600u);
    int valid = 0;
    for (std::size_t k = 0; k < r.per_point.size(); k += 7) {
      const PointEntropy& pe = r.per_point[k];
      EXPECT_EQ(pe.scan, k < 300 ? 0 : 1);
      const Vec3 p = inputPoint(pr, pe);
      const double radius = dynamicRadius(cfg, (p - (pe.scan ? pr.b.origin : pr.a.origin)).norm());
      EXPECT_FLOAT_EQ(pe.radius, static_cast<float>(radius));
      const PointEntropy bf = bruteForce(pr, p, pe.scan, radius, cfg);
      ASSERT_EQ(pe.valid, bf.valid) << "dynamic " << dynamic << " k " << k;
      ASSERT_EQ(pe.overlap, bf.overlap);
      ASSERT_EQ(pe.joint_ok, bf.joint_ok);
      if (pe.valid) {
        EXPECT_NEAR(pe.h_sep, bf.h_sep, 1e-4);
        EXPECT_NEAR(pe.h_joint, bf.h_joint, 1e-4);
        ++valid;
      }
    }
    EXPECT_GT(valid, 40) << "dynamic " << dynamic;
  }
}

TEST(CoralSubset, SubsetEntropiesEqualTheFullRunsForTheSamePoints) {
  const Pair pr = yardPair(22, 0.2);
  CoralConfig cfg = baseConfig();
  const CoralResult full = computeCoral(pr.a, pr.b, cfg);
  cfg.max_queries = 500;
  const CoralResult sub = computeCoral(pr.a, pr.b, cfg);
  std::map<std::tuple<int, float, float, float>, const PointEntropy*> by_pos;
  for (const PointEntropy& pe : full.per_point)
    by_pos[{pe.scan, pe.position.x(), pe.position.y(), pe.position.z()}] = &pe;
  for (const PointEntropy& pe : sub.per_point) {
    const auto it = by_pos.find({pe.scan, pe.position.x(), pe.position.y(), pe.position.z()});
    ASSERT_NE(it, by_pos.end());
    EXPECT_EQ(pe.valid, it->second->valid);
    if (pe.valid) {
      EXPECT_EQ(pe.h_sep, it->second->h_sep);
      EXPECT_EQ(pe.h_joint, it->second->h_joint);
    }
  }
}

TEST(CoralSubset, EstimatorIsUnbiasedAndItsStandardErrorMatchesTheSpreadOverSeeds) {
  for (double offset : {0.0, 0.3}) {
    const Pair pr = yardPair(23, offset);
    CoralConfig cfg = baseConfig();
    cfg.per_point = false;
    const CoralResult full = computeCoral(pr.a, pr.b, cfg);
    ASSERT_TRUE(full.valid);
    EXPECT_EQ(full.quality_stderr, 0.0);  // every point scored: exact
    cfg.max_queries = 400;
    const int seeds = 40;
    double sum = 0.0, sum2 = 0.0, se = 0.0;
    for (int s = 1; s <= seeds; ++s) {
      cfg.query_seed = s;
      const CoralResult r = computeCoral(pr.a, pr.b, cfg);
      ASSERT_TRUE(r.valid);
      ASSERT_EQ(r.num_queries, 800u);
      sum += r.quality;
      sum2 += r.quality * r.quality;
      se += r.quality_stderr;
      EXPECT_GT(r.h_joint_stderr, 0.0);
      EXPECT_GT(r.h_sep_stderr, 0.0);
    }
    const double mean = sum / seeds;
    const double sd = std::sqrt((sum2 - seeds * mean * mean) / (seeds - 1));
    se /= seeds;
    // Unbiased: the mean over seeds is within 4 standard errors of that mean of the full Q.
    EXPECT_NEAR(mean, full.quality, 4.0 * sd / std::sqrt(double(seeds)) + 1e-3)
        << "offset " << offset << " sd " << sd;
    // The reported standard error describes the real spread (stratification may make the
    // spread smaller than the simple-random-sampling formula, never much larger).
    EXPECT_GT(se, 0.0);
    EXPECT_LT(sd, 1.5 * se) << "offset " << offset;
    EXPECT_GT(sd, 0.25 * se) << "offset " << offset;
    // Misalignment is still seen through the subset.
    if (offset > 0) {
      EXPECT_GT(mean, 0.1);
    }
  }
}

TEST(CoralSubset, SameSeedSameSubsetAndSmallCloudsAreScoredWhole) {
  const Pair pr = yardPair(24, 0.0);
  CoralConfig cfg = baseConfig();
  cfg.max_queries = 250;
  const CoralResult r1 = computeCoral(pr.a, pr.b, cfg), r2 = computeCoral(pr.a, pr.b, cfg);
  EXPECT_EQ(r1.quality, r2.quality);
  cfg.query_seed = 2;
  EXPECT_NE(computeCoral(pr.a, pr.b, cfg).quality, r1.quality);
  cfg.max_queries = 1000000;  // more than the points: exactly the full result
  const CoralResult all = computeCoral(pr.a, pr.b, cfg);
  cfg.max_queries = 0;
  const CoralResult ref = computeCoral(pr.a, pr.b, cfg);
  EXPECT_EQ(all.quality, ref.quality);
  EXPECT_EQ(all.num_queries, pr.a.points.size() + pr.b.points.size());
}

TEST(CoralSubset, ResultsDoNotDependOnTheThreadCount) {
  const Pair pr = yardPair(25, 0.1);
  for (int max_queries : {0, 300}) {
    for (double leaf : {0.0, 0.1}) {
      CoralConfig cfg = baseConfig();
      cfg.max_queries = max_queries;
      cfg.voxel_leaf = leaf;
      cfg.e_reject = 0.1;
      const CoralResult one = computeCoral(pr.a, pr.b, cfg);
      for (int threads : {2, 3, 8}) {
        cfg.threads = threads;
        const CoralResult r = computeCoral(pr.a, pr.b, cfg);
        EXPECT_EQ(r.quality, one.quality) << threads << " threads";
        EXPECT_EQ(r.h_joint, one.h_joint);
        EXPECT_EQ(r.mme, one.mme);
        EXPECT_EQ(r.quality_stderr, one.quality_stderr);
        ASSERT_EQ(r.per_point.size(), one.per_point.size());
        for (std::size_t i = 0; i < r.per_point.size(); ++i) {
          ASSERT_EQ(r.per_point[i].position, one.per_point[i].position);
          ASSERT_EQ(r.per_point[i].valid, one.per_point[i].valid);
          ASSERT_EQ(r.per_point[i].h_joint, one.per_point[i].h_joint);
        }
      }
    }
  }
}

TEST(CoralSubset, VoxelFilterKeepsTheVerdictOnTheYard) {
  CoralConfig cfg = baseConfig();
  cfg.voxel_leaf = 0.1;
  const CoralResult aligned = computeCoral(yardPair(26, 0.0).a, yardPair(26, 0.0).b, cfg);
  const CoralResult off = computeCoral(yardPair(26, 0.3).a, yardPair(26, 0.3).b, cfg);
  ASSERT_TRUE(aligned.valid);
  EXPECT_LT(aligned.num_used_a, aligned.num_points_a);
  EXPECT_EQ(aligned.num_queries, aligned.num_used_a + aligned.num_used_b);
  EXPECT_LT(std::abs(aligned.quality), 0.1);
  EXPECT_GT(off.quality, aligned.quality + 0.2);
}

TEST(CoralSubset, ConfigValidation) {
  CoralConfig c;
  c.voxel_leaf = -0.1;
  EXPECT_NE(c.validate().find("voxel_leaf"), std::string::npos);
  c = CoralConfig();
  c.max_queries = -1;
  EXPECT_NE(c.validate().find("max_queries"), std::string::npos);
  c = CoralConfig();
  c.threads = 0;
  EXPECT_NE(c.validate().find("threads"), std::string::npos);
}
