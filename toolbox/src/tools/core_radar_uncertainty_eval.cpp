// Compares plain CorAl with uncertainty-aware CorAl (core/coral_uncertainty.hpp) on an
// Oxford Radar RobotCar folder: per consecutive pair, Q at ground truth versus Q with the
// later scan offset forward / backward / left / right (in its own sensor frame).
// Usage: coral_radar_uncertainty_eval [oxford_folder] (default ../shared/data/oxford_radar_tiny)
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/coral/coral_uncertainty.hpp"
#include "coral_introspection/eval/oxford_dataset.hpp"
#include "coral_introspection/eval/oxford_training.hpp"
#include "coral_introspection/eval/tool_args.hpp"
#include "coral_introspection/radar/polar_scan.hpp"
#include "coral_introspection/radar/radar_uncertainty.hpp"
#include "coral_introspection/radar/rip_features.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::radar;
using namespace coral_introspection::eval;

namespace {

struct Variant {
  std::string name;
  bool uncertain;
  UncertainCoralConfig cfg;  // cfg.base alone for plain CorAl
};

struct Tally {
  int wins = 0, total = 0;    // Q(gt) < Q(offset) within the same pair
  double margin_min = 1e9;    // min over pairs of Q(offset) - Q(gt) [nats]
  std::vector<double> q_off;  // every offset Q, for the pooled AUC
};

// Pooled AUC: probability that a GT pair scores below an offset pair, over all pairs
// (what one global classifier threshold can separate; scale free across variants).
double pooledAuc(const std::vector<double>& q_gt, const std::vector<double>& q_off) {
  double s = 0.0;
  for (double g : q_gt)
    for (double o : q_off) s += g < o ? 1.0 : (g == o ? 0.5 : 0.0);
  return s / (q_gt.size() * q_off.size());
}

}  // namespace

constexpr const char* kUsage =
    "usage: coral_radar_uncertainty_eval [oxford_folder] (default "
    "../shared/data/oxford_radar_tiny)";

int main(int argc, char** argv) {
  ToolArgs args;
  if (const auto exit =
          readCommandLine("coral_radar_uncertainty_eval", kUsage, argc, argv, {}, {}, &args, 1))
    return *exit;
  const std::string folder =
      args.positional.empty() ? "../shared/data/oxford_radar_tiny" : args.positional[0];
  OxfordDataset ds;
  std::string err;
  if (!ds.load(folder, &err)) {
    std::fprintf(stderr, "cannot load %s: %s\n", folder.c_str(), err.c_str());
    return 1;
  }
  // Features (paper Sec. V-A settings), de-skewed as in training and online (the policy of
  // radar/deskew.hpp on the GT poses), then the polar covariance of the Navtech preset in
  // each scan's own sensor frame.
  OxfordTrainingConfig ocfg;
  ocfg.with_cfear = false;
  std::vector<TrainingScan> loaded;
  Isometries poses;
  if (!loadOxfordTrainingScans(ds, ocfg, nullptr, &loaded, &poses, &err)) {
    std::fprintf(stderr, "%s\n", err.c_str());
    return 1;
  }
  std::vector<Scan> scans;
  for (TrainingScan& t : loaded) {
    attachCovariances(t.scan, RadarNoiseConfig::oxfordCts350x(), 2, &err);
    scans.push_back(t.scan);
  }

  std::vector<Variant> variants;
  for (double r : {0.75, 1.0}) {  // r = 1 m is the paper's radar setting (Sec. V-A)
    Variant plain{"plain CorAl r=" + std::to_string(r).substr(0, 4), false, {}};
    plain.cfg.base.dimension = 2;
    plain.cfg.base.radius = r;
    variants.push_back(plain);
  }
  for (double gate : {3.0, 6.0, 12.0})
    for (double r_min : {0.5, 0.75, 1.0}) {
      Variant v{"", true, {}};
      v.cfg.base.dimension = 2;
      v.cfg.base.r_min = r_min;
      v.cfg.base.r_max = 3.0;
      v.cfg.gate_sigma = gate;
      char name[96];
      std::snprintf(name, sizeof(name), "uncertain gate=%.0f r_min=%.2f r_max=3", gate, r_min);
      v.name = name;
      variants.push_back(v);
    }

  std::printf("%zu scans, %zu pairs\n", scans.size(), scans.size() - 1);
  for (const Variant& v : variants) {
    Tally t03, t05;
    double seconds = 0.0, overlap = 0.0;
    std::vector<double> q_gt;
    for (std::size_t i = 1; i < scans.size(); ++i) {
      auto score = [&](const Eigen::Isometry3d& T) {
        const Scan b = transformScan(scans[i], T);
        const CoralResult r = v.uncertain ? computeCoralUncertain(scans[i - 1], b, v.cfg)
                                          : computeCoral(scans[i - 1], b, v.cfg.base);
        seconds += r.seconds;
        return r;
      };
      const CoralResult gt = score(ds.T_prev_curr[i]);
      overlap += gt.overlap;
      q_gt.push_back(gt.quality);
      for (double off : {0.3, 0.5}) {
        Tally& t = off < 0.4 ? t03 : t05;
        for (const Eigen::Isometry3d& d :
             {se2(off, 0, 0), se2(-off, 0, 0), se2(0, off, 0), se2(0, -off, 0)}) {
          const double q = score(ds.T_prev_curr[i] * d).quality;
          t.wins += q > gt.quality;
          ++t.total;
          t.margin_min = std::min(t.margin_min, q - gt.quality);
          t.q_off.push_back(q);
        }
      }
    }
    const double pairs = scans.size() - 1;
    std::printf(
        "%-38s 0.3 m: %2d/%d AUC %.3f (min margin %+.3f)  0.5 m: %2d/%d AUC %.3f "
        "(min margin %+.3f)  overlap %.2f  %.1f ms/pair\n",
        v.name.c_str(), t03.wins, t03.total, pooledAuc(q_gt, t03.q_off), t03.margin_min, t05.wins,
        t05.total, pooledAuc(q_gt, t05.q_off), t05.margin_min, overlap / pairs,
        1e3 * seconds / (pairs * 9));
  }
  return 0;
}
