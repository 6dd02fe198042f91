// Training / evaluation samples at the user's tolerance (tolerance.hpp): for every pair with
// an accurate relative pose, the aligned sample (optionally also aligned samples a share of
// the tolerance off, `aligned_spread`) and one misaligned sample per tolerance offset
// (T_a_b * Delta, b's sensor frame; paper Sec. III-F), each with
//  - method "CorAl": H_joint, H_sep at the sample's pose (the classifier inputs, Eq. 9);
//  - method "Relative": Q at the sample's pose and at each tolerance neighbour of it
//    (the relative check's inputs, relative_check.hpp).
// Pairs are processed on every core; the result does not depend on the thread count.
// A shard (index i of n: pairs with pair % n == i) lets a job array split a data set.
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/coral/tolerance.hpp"
#include "coral_introspection/eval/training_set.hpp"

namespace coral_introspection {
namespace eval {

struct VerdictSampleConfig {
  coral::CoralConfig coral;          // the preset's CorAl settings
  coral::ToleranceConfig tolerance;  // size of the induced misalignments and of the probes
  int probe_queries = 0;             // queries per scan of the relative check's Q values
                                     // (RelativeCheckConfig::probe_queries; 0 = all)
  double aligned_spread = 0.0;       // [tolerances] in [0, 1): also label aligned the poses this
                                     // share of the tolerance off along each axis (a loop
                                     // registration stops short of the exact pose); 0 = only
                                     // the exact pose (paper Sec. III-F)
  int threads = 0;                   // worker threads; 0 = every core of the machine
  int shard_index = 0;               // this shard ...
  int shard_count = 1;               // ... of this many (1 = the whole data set)
  std::string validate() const;      // empty when valid
};

// Group labels of the misaligned samples: offsets along x, y, z / about roll, pitch, yaw.
extern const char* const kTranslationGroup;  // "translation"
extern const char* const kRotationGroup;     // "rotation"

// Method specs of a verdict sample set for a CorAl dimension (2 or 3).
std::vector<MethodSpec> verdictMethods(int dimension);

// Samples of the shard's pairs, ordered by pair index, labelled with `dataset`. False with
// *error on an invalid config or a pair that refers to a missing scan; never throws.
// *cost (optional) receives the computeCoral calls made and their summed wall time.
struct CoralCost {
  std::size_t evaluations = 0;
  double seconds = 0.0;  // summed over threads
};
bool buildVerdictSamples(const std::string& dataset, const std::vector<TrainingScan>& scans,
                         const std::vector<ScanPair>& pairs, const VerdictSampleConfig& cfg,
                         const Progress& progress, SampleSet* set, std::string* error,
                         CoralCost* cost = nullptr);

}  // namespace eval
}  // namespace coral_introspection
