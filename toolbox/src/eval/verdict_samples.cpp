#include "coral_introspection/eval/verdict_samples.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "coral_introspection/coral/coral_pair.hpp"
#include "coral_introspection/coral/types.hpp"
#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace eval {

const char* const kTranslationGroup = "translation";
const char* const kRotationGroup = "rotation";

std::string VerdictSampleConfig::validate() const {
  return coral::Problems()
      .nested("coral", coral.validate())
      .nested("tolerance", tolerance.validate())
      .require(threads >= 0, "threads", ">= 0", threads)
      .require(probe_queries >= 0, "probe_queries", ">= 0", probe_queries)
      .require(aligned_spread >= 0.0 && aligned_spread < 1.0, "aligned_spread", "in [0, 1)",
               aligned_spread)
      .require(shard_count >= 1, "shard_count", ">= 1", shard_count)
      .require(shard_index >= 0 && shard_index < shard_count, "shard_index", "in [0, shard_count)",
               shard_index)
      .str();
}

std::vector<MethodSpec> verdictMethods(int dimension) {
  MethodSpec rel{"Relative", {"Q"}};
  for (const coral::ToleranceOffset& o :
       coral::toleranceOffsets(coral::ToleranceConfig(), dimension))
    rel.feature_names.push_back("Q_" + o.name);
  return {{"CorAl", {"H_joint", "H_sep"}}, rel};
}

namespace {

// CorAl of one pair at many offsets Delta (b's frame) on one CoralPair, as judgeAlignment
// evaluates it online; each pose computed once: neighbours of neighbouring samples coincide
// (x+ then x- is the aligned pose).
class PairEvaluator {
 public:
  using Key = std::array<long long, 12>;
  PairEvaluator(const coral::Scan& a, const coral::Scan& b, const Eigen::Isometry3d& T_a_b,
                coral::CoralConfig c, int probe_queries)
      : pair_(a, b, noPerPoint(c), probe_queries), T_a_b_(T_a_b) {}
  // {H_joint, H_sep, Q} over every query, NaN without a valid CorAl result; also fills the
  // probe Q of this pose.
  const std::array<double, 3>& at(const Eigen::Isometry3d& delta) {
    const Key k = key(delta);
    auto it = full_.find(k);
    if (it != full_.end()) return it->second;
    coral::CoralResult probe;
    const coral::CoralResult r = pair_.evaluate(T_a_b_ * delta, &probe);
    count(r);
    probe_[k] = probe.valid ? probe.quality : nan();
    std::array<double, 3> v = {nan(), nan(), nan()};
    if (r.valid) v = {r.h_joint, r.h_sep, r.quality};
    return full_.emplace(k, v).first->second;
  }
  // Q over the probe queries (what the relative check compares).
  double probeQ(const Eigen::Isometry3d& delta) {
    const Key k = key(delta);
    auto it = probe_.find(k);
    if (it != probe_.end()) return it->second;
    const coral::CoralResult r = pair_.evaluateProbe(T_a_b_ * delta);
    count(r);
    return probe_[k] = r.valid ? r.quality : nan();
  }
  const CoralCost& cost() const { return cost_; }

 private:
  static coral::CoralConfig noPerPoint(coral::CoralConfig c) {
    c.per_point = false;
    return c;
  }
  static double nan() { return std::numeric_limits<double>::quiet_NaN(); }
  static Key key(const Eigen::Isometry3d& delta) {  // rounded (1 um, 1e-9 of the rotation)
    Key k;
    for (int i = 0; i < 3; ++i) {
      k[i] = std::llround(delta.translation()[i] * 1e6);
      for (int j = 0; j < 3; ++j) k[3 + 3 * i + j] = std::llround(delta.linear()(i, j) * 1e9);
    }
    return k;
  }
  void count(const coral::CoralResult& r) {
    ++cost_.evaluations;
    cost_.seconds += r.seconds;
  }
  coral::CoralPair pair_;
  Eigen::Isometry3d T_a_b_;
  CoralCost cost_;
  std::map<Key, std::array<double, 3>> full_;
  std::map<Key, double> probe_;
};

// One sample to compute: its offset from the pose and its label.
struct SampleSpec {
  Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
  std::string offset = Sample().offset;  // "aligned" for the exact pose
  std::string group;                     // "" for every aligned sample
  int label = 1;
};

// The exact pose, the aligned poses `aligned_spread` tolerances off (named "x+@0.5", ...) and
// the misaligned one-tolerance offsets, in this order.
std::vector<SampleSpec> sampleSpecs(const VerdictSampleConfig& cfg,
                                    const std::vector<coral::ToleranceOffset>& offsets) {
  std::vector<SampleSpec> specs(1);  // the exact pose
  if (cfg.aligned_spread > 0.0) {
    coral::ToleranceConfig near = cfg.tolerance;
    near.translation *= cfg.aligned_spread;
    near.rotation_deg *= cfg.aligned_spread;
    std::ostringstream share;
    share << "@" << cfg.aligned_spread;
    for (const coral::ToleranceOffset& o : coral::toleranceOffsets(near, cfg.coral.dimension))
      specs.push_back({o.delta, o.name + share.str(), "", 1});
  }
  for (const coral::ToleranceOffset& o : offsets)
    specs.push_back(
        {o.delta, o.name, coral::isRotation(o.axis) ? kRotationGroup : kTranslationGroup, 0});
  return specs;
}

std::vector<Sample> pairSamples(const std::string& dataset, int pair_index,
                                const std::vector<TrainingScan>& scans, const ScanPair& pr,
                                const std::vector<coral::ToleranceOffset>& offsets,
                                const std::vector<SampleSpec>& specs,
                                const VerdictSampleConfig& cfg, CoralCost* cost) {
  PairEvaluator eval(scans[pr.a].scan, scans[pr.b].scan, pr.T_a_b, cfg.coral, cfg.probe_queries);
  std::vector<Sample> out;
  for (const SampleSpec& spec : specs) {
    Sample x;
    x.pair = pair_index;
    x.dataset = dataset;
    x.stamp_a = scans[pr.a].stamp;
    x.stamp_b = scans[pr.b].stamp;
    const Eigen::Isometry3d& delta = spec.delta;
    x.offset = spec.offset;
    x.group = spec.group;
    x.label = spec.label;
    x.dx = delta.translation().x();  // 0 for the exact pose
    x.dy = delta.translation().y();
    x.dyaw = coral::yawOf(delta.linear());
    const std::array<double, 3> c = eval.at(delta);
    x.features = {{c[0], c[1]}, {eval.probeQ(delta)}};  // the relative check's Q: probe queries
    for (const coral::ToleranceOffset& o : offsets)
      x.features[1].push_back(eval.probeQ(delta * o.delta));
    out.push_back(std::move(x));
  }
  cost->evaluations += eval.cost().evaluations;
  cost->seconds += eval.cost().seconds;
  return out;
}

}  // namespace

bool buildVerdictSamples(const std::string& dataset, const std::vector<TrainingScan>& scans,
                         const std::vector<ScanPair>& pairs, const VerdictSampleConfig& cfg,
                         const Progress& progress, SampleSet* set, std::string* error,
                         CoralCost* cost) {
  if (const std::string e = cfg.validate(); !e.empty()) return coral::fail(error, e);
  std::vector<int> mine;  // pair indices of this shard
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const ScanPair& p = pairs[i];
    if (p.a < 0 || p.b < 0 || p.a >= static_cast<int>(scans.size()) ||
        p.b >= static_cast<int>(scans.size()))
      return coral::fail(error, "pair " + std::to_string(i) + " refers to a missing scan");
    if (static_cast<int>(i % cfg.shard_count) == cfg.shard_index)
      mine.push_back(static_cast<int>(i));
  }
  const std::vector<coral::ToleranceOffset> offsets =
      coral::toleranceOffsets(cfg.tolerance, cfg.coral.dimension);
  const std::vector<SampleSpec> specs = sampleSpecs(cfg, offsets);
  std::vector<std::vector<Sample>> per_pair(mine.size());
  std::vector<CoralCost> costs(mine.size());
  std::atomic<std::size_t> next{0};
  std::size_t done = 0;
  std::mutex progress_mutex;
  auto worker = [&] {
    for (std::size_t k; (k = next++) < mine.size();) {
      per_pair[k] =
          pairSamples(dataset, mine[k], scans, pairs[mine[k]], offsets, specs, cfg, &costs[k]);
      std::lock_guard<std::mutex> lock(progress_mutex);
      if (progress) progress(++done, mine.size());
    }
  };
  unsigned n = cfg.threads > 0 ? cfg.threads : std::max(1u, std::thread::hardware_concurrency());
  n = std::min<unsigned>(n, std::max<std::size_t>(1, mine.size()));
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < n; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();

  for (const CoralCost& c : costs)
    if (cost) {
      cost->evaluations += c.evaluations;
      cost->seconds += c.seconds;
    }
  set->methods = verdictMethods(cfg.coral.dimension);
  set->groups = {kTranslationGroup, kRotationGroup};
  set->samples.clear();
  for (std::vector<Sample>& v : per_pair)
    for (Sample& s : v) set->samples.push_back(std::move(s));
  return true;
}

}  // namespace eval
}  // namespace coral_introspection
