#include "coral_introspection/eval/training_set.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace coral_introspection {
namespace eval {

FeatureConfig FeatureConfig::radar() {
  FeatureConfig c;
  c.coral = coral::CoralConfig::radarPaper();  // Sec. V-A c
  c.coral.per_point = false;
  c.ndt.dimension = 2;
  c.ndt.voxel_size = 2.0;  // v = 2 r (Sec. IV-1 d)
  return c;
}

FeatureConfig FeatureConfig::lidar() {
  FeatureConfig c;
  c.coral.dimension = 3;
  c.coral.radius = 0.3;  // Sec. IV-B
  c.coral.e_reject = 0.2;
  c.coral.per_point = false;
  c.ndt.dimension = 3;
  c.ndt.voxel_size = 0.6;
  c.with_cfear = false;
  return c;
}

std::string FeatureConfig::validate() const {
  for (const std::string& e : {coral.validate(), ndt.validate(), cfear.validate()})
    if (!e.empty()) return e;
  if (coral.dimension != ndt.dimension) return "coral.dimension and ndt.dimension differ";
  return "";
}

std::vector<MethodSpec> methodSpecs(const FeatureConfig& cfg) {
  // Classifier inputs as in Sec. IV-1 and V-A: x1 = H_joint, x2 = H_sep for CorAl; a single
  // input for MME and NDT; NDT score + NDT-entropy for Rel-NDT; absolute score,
  // correspondences and normalized score for CFEAR.
  std::vector<MethodSpec> m = {{"CorAl", {"H_joint", "H_sep"}},
                               {"CorAl-median", {"H_joint", "H_sep"}},
                               {"MME", {"H_joint"}},
                               {"NDT", {"score"}},
                               {"Rel-NDT", {"score", "ndt_entropy"}}};
  if (cfg.with_cfear)
    for (const char* n : {"CFEAR-P2P", "CFEAR-P2L", "CFEAR-P2D"})
      m.push_back({n, {"sum", "correspondences", "normalized"}});
  return m;
}

std::vector<ScanPair> makePairs(const coral::Isometries& T, double min_spacing) {
  std::vector<ScanPair> pairs;
  for (std::size_t a = 0; a + 1 < T.size(); ++a) {
    std::size_t b = a + 1;
    if (min_spacing > 0.0)
      while (b < T.size() && (T[b].translation() - T[a].translation()).norm() < min_spacing) ++b;
    if (b >= T.size()) break;
    pairs.push_back({static_cast<int>(a), static_cast<int>(b), T[a].inverse() * T[b]});
  }
  return pairs;
}

std::vector<std::vector<double>> computeFeatures(const TrainingScan& a, const TrainingScan& b,
                                                 const SurfacePoints& surf_a,
                                                 const SurfacePoints& surf_b,
                                                 const Eigen::Isometry3d& T_a_b,
                                                 const FeatureConfig& cfg) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const coral::Scan b_in_a =
      coral::transformScan(b.scan, T_a_b);  // origin moves with it (dynamic radius)
  const coral::CoralResult mean = coral::computeCoral(a.scan, b_in_a, cfg.coral);
  coral::CoralConfig median_cfg = cfg.coral;
  median_cfg.aggregation = coral::Aggregation::kMedian;
  const coral::CoralResult median = coral::computeCoral(a.scan, b_in_a, median_cfg);
  const NdtResult ndt = computeNdtScore(a.scan.points, b_in_a.points, cfg.ndt);

  std::vector<std::vector<double>> f;
  f.push_back(mean.valid ? std::vector<double>{mean.h_joint, mean.h_sep}
                         : std::vector<double>{nan, nan});
  f.push_back(median.valid ? std::vector<double>{median.h_joint, median.h_sep}
                           : std::vector<double>{nan, nan});
  f.push_back({mean.num_points_a + mean.num_points_b > 0 ? mean.mme : nan});
  f.push_back({ndt.valid ? ndt.score : nan});
  f.push_back(ndt.valid ? std::vector<double>{ndt.score, ndt.entropy}
                        : std::vector<double>{nan, nan});
  if (cfg.with_cfear) {
    const CfearScores c =
        computeCfearScores(surf_a, transformSurfacePoints(surf_b, T_a_b), cfg.cfear);
    for (const CfearScore* s : {&c.p2p, &c.p2l, &c.p2d})
      f.push_back(c.valid ? std::vector<double>{s->sum, s->count, s->normalized}
                          : std::vector<double>{nan, nan, nan});
  }
  return f;
}

bool buildSampleSet(const std::vector<TrainingScan>& scans, const std::vector<ScanPair>& pairs,
                    const std::vector<Perturbation>& perturbations, const FeatureConfig& cfg,
                    const Progress& progress, SampleSet* set, std::string* error) {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (const std::string e = cfg.validate(); !e.empty()) return fail(e);
  set->methods = methodSpecs(cfg);
  set->groups.clear();
  for (const Perturbation& p : perturbations)
    if (std::find(set->groups.begin(), set->groups.end(), p.group) == set->groups.end())
      set->groups.push_back(p.group);
  set->samples.clear();
  // CFEAR surfaces depend only on the scan: compute each once, in its own frame.
  std::vector<SurfacePoints> surfaces(scans.size());
  if (cfg.with_cfear)
    for (std::size_t i = 0; i < scans.size(); ++i)
      surfaces[i] = computeSurfacePoints(scans[i].cfear_points, cfg.cfear);
  const std::size_t total = pairs.size() * (1 + perturbations.size());
  std::size_t done = 0;
  for (std::size_t pi = 0; pi < pairs.size(); ++pi) {
    const ScanPair& pr = pairs[pi];
    if (pr.a < 0 || pr.b < 0 || pr.a >= static_cast<int>(scans.size()) ||
        pr.b >= static_cast<int>(scans.size()))
      return fail("pair " + std::to_string(pi) + " refers to a missing scan");
    Sample s;
    s.pair = static_cast<int>(pi);
    s.stamp_a = scans[pr.a].stamp;
    s.stamp_b = scans[pr.b].stamp;
    s.features =
        computeFeatures(scans[pr.a], scans[pr.b], surfaces[pr.a], surfaces[pr.b], pr.T_a_b, cfg);
    set->samples.push_back(s);
    if (progress) progress(++done, total);
    for (const Perturbation& p : perturbations) {
      Sample m = s;
      m.offset = p.name;
      m.group = p.group;
      m.dx = p.dx;
      m.dy = p.dy;
      m.dyaw = p.dyaw;
      m.label = 0;
      m.features = computeFeatures(scans[pr.a], scans[pr.b], surfaces[pr.a], surfaces[pr.b],
                                   perturb(pr.T_a_b, p), cfg);  // T_a_b * Delta
      set->samples.push_back(m);
      if (progress) progress(++done, total);
    }
  }
  return true;
}

}  // namespace eval
}  // namespace coral_introspection
