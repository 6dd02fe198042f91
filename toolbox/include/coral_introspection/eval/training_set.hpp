// Self-supervised training samples (paper Sec. III-F): for every scan pair with an accurate
// relative pose, the quality measures of the aligned pair and of each induced
// misalignment (perturbation.hpp), for CorAl and every baseline of Sec. IV / V-A.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/eval/cfear_scores.hpp"
#include "coral_introspection/eval/evaluation.hpp"
#include "coral_introspection/eval/ndt.hpp"
#include "coral_introspection/eval/perturbation.hpp"

namespace coral_introspection {
namespace eval {

// One scan in its own sensor frame.
struct TrainingScan {
  double stamp = 0.0;          // [s]
  coral::Scan scan;            // CorAl / MME / NDT input (radar: RIP features), origin = sensor
  coral::Points cfear_points;  // CFEAR input (radar: k-strongest points); empty = no CFEAR methods
};

struct ScanPair {
  int a = 0, b = 0;                                         // scan indices, a earlier
  Eigen::Isometry3d T_a_b = Eigen::Isometry3d::Identity();  // maps b's points into a's frame
};

struct FeatureConfig {
  coral::CoralConfig coral;  // CorAl and MME; CorAl-median uses it with kMedian
  NdtConfig ndt;             // NDT and Rel-NDT
  CfearConfig cfear;         // CFEAR-P2P/P2L/P2D (only when scans carry cfear_points)
  bool with_cfear = true;
  // Paper's radar settings (Sec. V-A): 2D, r = 1 m, E_reject = 0, epsilon = 0, v = 2r.
  static FeatureConfig radar();
  // Paper's lidar settings (Sec. IV-B): 3D, r = 0.3 m, E_reject = 0.2, v = 0.6 m.
  static FeatureConfig lidar();
  std::string validate() const;  // empty when valid
};

// CorAl, CorAl-median, MME, NDT, Rel-NDT (+ CFEAR-P2P, -P2L, -P2D) with their inputs.
std::vector<MethodSpec> methodSpecs(const FeatureConfig& cfg);

// Pairs from poses T_first_i (scan i in a common frame): min_spacing <= 0 gives
// consecutive pairs (i-1, i); otherwise each scan a is paired with the first later scan
// at least min_spacing metres away (the paper's "scans taken at least X m apart").
std::vector<ScanPair> makePairs(const coral::Isometries& T_first_scan, double min_spacing);

// Features of every method for b placed into a's frame with T_a_b (NaN where a method has
// no valid value). surf_a / surf_b are the CFEAR surfaces of a and b in their own frames.
std::vector<std::vector<double>> computeFeatures(const TrainingScan& a, const TrainingScan& b,
                                                 const SurfacePoints& surf_a,
                                                 const SurfacePoints& surf_b,
                                                 const Eigen::Isometry3d& T_a_b,
                                                 const FeatureConfig& cfg);

using Progress = std::function<void(std::size_t done, std::size_t total)>;

// Aligned sample + one per perturbation for every pair. False with *error on an invalid
// config or pair index; never throws.
bool buildSampleSet(const std::vector<TrainingScan>& scans, const std::vector<ScanPair>& pairs,
                    const std::vector<Perturbation>& perturbations, const FeatureConfig& cfg,
                    const Progress& progress, SampleSet* set, std::string* error);

}  // namespace eval
}  // namespace coral_introspection
