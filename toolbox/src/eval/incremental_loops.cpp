#include "coral_introspection/eval/incremental_loops.hpp"

#include <algorithm>
#include <limits>

#include "coral_introspection/coral/refinement.hpp"
#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace eval {

namespace {

// Optimises keyframes 0..last over the edges between them; the rest follow by odometry from
// keyframe `last`, as a running back end's estimate of keyframes not yet optimised would.
bool solvePrefix(const std::vector<PoseGraphEdge>& edges, int last, const PoseGraphConfig& graph,
                 const coral::Isometries& T_world_odom, coral::Isometries* est,
                 PoseGraphResult* res, std::string* error) {
  std::vector<PoseGraphEdge> sub;
  for (const PoseGraphEdge& e : edges)
    if (std::max(e.from, e.to) <= last) sub.push_back(e);
  coral::Isometries prefix(est->begin(), est->begin() + last + 1);
  if (!optimizePoseGraph(sub, graph, &prefix, res)) return coral::fail(error, res->error);
  std::copy(prefix.begin(), prefix.end(), est->begin());
  for (std::size_t k = static_cast<std::size_t>(last) + 1; k < est->size(); ++k)
    (*est)[k] = (*est)[k - 1] * (T_world_odom[k - 1].inverse() * T_world_odom[k]);
  return true;
}

}  // namespace

bool closeLoopsIncrementally(const std::vector<TrainingScan>& scans,
                             const coral::Isometries& T_world_odom, const LoopCandidateConfig& cfg,
                             const std::vector<PoseGraphEdge>& odometry,
                             const std::vector<PoseGraphEdge>& seeds, const PoseGraphConfig& graph,
                             const LoopDecision& decide, coral::Isometries* poses,
                             IncrementalLoops* out, std::string* error, const EdgeCheck& admit) {
  if (const std::string e = cfg.validate(); !e.empty()) return coral::fail(error, e);
  if (const std::string e = graph.validate(); !e.empty()) return coral::fail(error, e);
  const int n = static_cast<int>(scans.size());
  if (T_world_odom.size() != scans.size())
    return coral::fail(error, "scans and odometry poses differ in number");
  *out = IncrementalLoops{};
  coral::Isometries est = T_world_odom;
  std::vector<PoseGraphEdge> edges = odometry;
  std::vector<char> seeded(seeds.size(), 0);
  for (int i = 0; i < n; ++i) {
    // Seeds whose two ends have arrived.
    bool changed = false;
    for (std::size_t s = 0; s < seeds.size(); ++s)
      if (!seeded[s] && std::max(seeds[s].from, seeds[s].to) == i) {
        seeded[s] = 1;
        if (admit && !admit(seeds[s], static_cast<int>(s))) {
          ++out->refused;
          continue;
        }
        edges.push_back(seeds[s]);
        out->loop_edges.push_back(seeds[s]);
        changed = true;
      }
    // The nearest earlier keyframe within the radius in the current estimate.
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (int j = 0; j + cfg.min_index_gap <= i; ++j) {
      const double d = (est[j].translation() - est[i].translation()).head<2>().norm();
      if (d <= cfg.radius && d < best_d) best = j, best_d = d;
    }
    if (best >= 0) {
      LoopCandidate c;
      c.a = best;
      c.b = i;
      c.source = "radius";
      registerPair(scans[best].scan.points, scans[i].scan.points, est[best].inverse() * est[i], cfg,
                   &c);
      Eigen::Isometry3d T_edge = c.T_a_b;
      const bool accepted = decide(c, &T_edge);
      const PoseGraphEdge e{c.a, c.b, T_edge, kLoopEdgeSigmaT, kLoopEdgeSigmaR, true};
      if (accepted && admit && !admit(e, -1)) {
        ++out->refused;
      } else if (accepted) {
        edges.push_back(e);
        out->loop_edges.push_back(e);
        // An edge the estimate already agrees with (within half a tolerance) waits for the
        // next solve: on a revisit every keyframe brings one, and one solve per edge would
        // cost a graph optimisation per keyframe.
        changed = changed || coral::toleranceSize(T_edge.inverse() * est[c.a].inverse() * est[c.b],
                                                  cfg.tolerance) > 0.5;
      }
      out->proposed.push_back(c);
    }
    if (changed) {
      if (!solvePrefix(edges, i, graph, T_world_odom, &est, &out->last, error)) return false;
      ++out->solves;
    }
  }
  if (!solvePrefix(edges, n - 1, graph, T_world_odom, &est, &out->last, error)) return false;
  ++out->solves;
  *poses = est;
  return true;
}

std::vector<std::optional<Eigen::Isometry3d>> scanMatchedSteps(
    const std::vector<TrainingScan>& scans, const coral::Isometries& T_world_odom,
    const LoopCandidateConfig& cfg, const LoopDecision& accept) {
  std::vector<std::optional<Eigen::Isometry3d>> steps;
  if (scans.size() < 2 || T_world_odom.size() != scans.size()) return steps;
  for (std::size_t k = 1; k < scans.size(); ++k) {
    LoopCandidate c;
    c.a = static_cast<int>(k) - 1;
    c.b = static_cast<int>(k);
    c.source = "odometry";
    const Eigen::Isometry3d step = T_world_odom[k - 1].inverse() * T_world_odom[k];
    registerPair(scans[k - 1].scan.points, scans[k].scan.points, step, cfg, &c);
    Eigen::Isometry3d T = c.T_a_b;
    steps.push_back(c.converged && accept(c, &T) ? std::optional<Eigen::Isometry3d>(T)
                                                 : std::nullopt);
  }
  return steps;
}

coral::Isometries scanMatchedOdometry(const std::vector<TrainingScan>& scans,
                                      const coral::Isometries& T_world_odom,
                                      const LoopCandidateConfig& cfg, const LoopDecision& accept,
                                      int* accepted) {
  *accepted = 0;
  if (scans.empty() || T_world_odom.size() != scans.size()) return {};
  const auto steps = scanMatchedSteps(scans, T_world_odom, cfg, accept);
  coral::Isometries chain = {T_world_odom[0]};
  for (std::size_t k = 0; k < steps.size(); ++k) {
    *accepted += steps[k] ? 1 : 0;
    chain.push_back(chain.back() *
                    (steps[k] ? *steps[k] : T_world_odom[k].inverse() * T_world_odom[k + 1]));
  }
  return chain;
}

bool calibratedOdometry(const std::vector<TrainingScan>& scans,
                        const coral::Isometries& T_world_odom, const LoopCandidateConfig& cfg,
                        const LoopDecision& accept, coral::Isometries* calibrated,
                        OdometryYawModel* model, std::string* error) {
  // 20 steps: a few turns and straights; the logs give hundreds.
  if (!fitOdometryYaw(T_world_odom, scanMatchedSteps(scans, T_world_odom, cfg, accept), 20, model,
                      error))
    return false;
  *calibrated = correctOdometryYaw(T_world_odom, *model);
  return true;
}

}  // namespace eval
}  // namespace coral_introspection
