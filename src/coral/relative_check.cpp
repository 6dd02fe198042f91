#include "coral_introspection/coral/relative_check.hpp"

#include <algorithm>
#include <cmath>

#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace coral {

std::string RelativeCheckConfig::validate() const {
  return Problems()
      .require(margin >= 0.0 && margin < 2.0, "relative_margin", "in [0, 2)", margin)
      .require(flat_ratio >= 0.0 && flat_ratio < 1.0, "flat_ratio", "in [0, 1)", flat_ratio)
      .require(probe_queries == 0 || probe_queries >= kMinProbeQueries, "probe_queries",
               ("0 (every CorAl query) or >= " + std::to_string(kMinProbeQueries) +
                ": fewer change the relative check's decisions on real pairs and judge ground "
                "truth misaligned (doc/coral_core.md)")
                   .c_str(),
               probe_queries)
      .str();
}

std::vector<CoralResult> neighbourResults(const CoralPair& pair, const Eigen::Isometry3d& T_a_b,
                                          const std::vector<ToleranceOffset>& offsets) {
  std::vector<CoralResult> out;
  for (const ToleranceOffset& o : offsets)  // only the aggregates are kept
    out.push_back(pair.evaluate(T_a_b * o.delta, nullptr, /*per_point=*/false));
  return out;
}

std::vector<double> neighbourQualities(const CoralPair& pair, const Eigen::Isometry3d& T_a_b,
                                       const std::vector<ToleranceOffset>& offsets) {
  std::vector<double> q;
  for (const ToleranceOffset& o : offsets) {
    const CoralResult r = pair.evaluateProbe(T_a_b * o.delta);
    q.push_back(r.valid ? r.quality : std::numeric_limits<double>::quiet_NaN());
  }
  return q;
}

RelativeCheckResult decideRelative(double q, const std::vector<ToleranceOffset>& offsets,
                                   const std::vector<double>& q_neighbours,
                                   const RelativeCheckConfig& cfg) {
  RelativeCheckResult r;
  r.q = q;
  int lowest = -1;
  for (std::size_t i = 0; i < offsets.size() && i < q_neighbours.size(); ++i) {
    const double qn = q_neighbours[i];
    auto it = std::find_if(r.axes.begin(), r.axes.end(),
                           [&](const AxisProbe& p) { return p.axis == offsets[i].axis; });
    if (it == r.axes.end()) {
      r.axes.push_back(AxisProbe());
      it = r.axes.end() - 1;
      it->axis = offsets[i].axis;
    }
    (offsets[i].sign > 0 ? it->q_plus : it->q_minus) = qn;
    if (!std::isfinite(qn) || !std::isfinite(q)) continue;
    if (lowest < 0 || qn < q_neighbours[lowest]) lowest = static_cast<int>(i);
  }
  for (AxisProbe& p : r.axes) {  // S_k = mean |Q_neighbour - Q|, s_k = (Q - min) / S_k
    int n = 0;
    double lowest_k = std::numeric_limits<double>::infinity();
    for (double qn : {p.q_plus, p.q_minus})
      if (std::isfinite(qn) && std::isfinite(q)) {
        p.sensitivity += std::abs(qn - q);
        lowest_k = std::min(lowest_k, qn);
        ++n;
      }
    p.valid = n > 0;
    if (n > 0) p.sensitivity /= n;
    if (p.sensitivity > 0.0) {
      p.score = (q - lowest_k) / p.sensitivity;
      r.score = std::isfinite(r.score) ? std::max(r.score, p.score) : p.score;
    }
    r.scale = std::max(r.scale, p.sensitivity);
  }
  if (lowest < 0 || !std::isfinite(r.score)) return r;
  r.valid = true;
  for (AxisProbe& p : r.axes) {
    p.flat = p.valid && p.sensitivity < cfg.flat_ratio * r.scale;
    if (p.flat) r.flat_axes.push_back(p.axis);
  }
  r.misaligned = exceedsMargin(r, cfg);
  if (q_neighbours[lowest] < q) r.hint = offsets[lowest];
  return r;
}

std::vector<Axis> horizontalFlatAxes(const std::vector<Axis>& flat) {
  std::vector<Axis> out;
  for (Axis a : flat)
    if (a == Axis::kX || a == Axis::kY || a == Axis::kYaw) out.push_back(a);
  return out;
}

bool exceedsMargin(const RelativeCheckResult& r, const RelativeCheckConfig& cfg) {
  return r.valid && r.score > cfg.margin;
}

RelativeCheckResult relativeCheck(const CoralPair& pair, const Eigen::Isometry3d& T_a_b,
                                  const CoralResult& at_pose_probe, int dimension,
                                  const ToleranceConfig& tolerance,
                                  const RelativeCheckConfig& cfg) {
  if (!at_pose_probe.valid) return RelativeCheckResult();  // no Q to compare with: no probes
  const std::vector<ToleranceOffset> offsets = toleranceOffsets(tolerance, dimension);
  RelativeCheckResult r =
      decideRelative(at_pose_probe.quality, offsets, neighbourQualities(pair, T_a_b, offsets), cfg);
  r.coral_evaluations = static_cast<int>(offsets.size());
  return r;
}

}  // namespace coral
}  // namespace coral_introspection
