#include "coral_introspection/eval/carmen_loops.hpp"

#include "coral_introspection/eval/pose_graph.hpp"

namespace coral_introspection {
namespace eval {

bool loadCarmenLoopSet(const std::string& log_path, const std::string& corrected_csv,
                       const std::string& relations_path, const LoopCandidateConfig& cfg,
                       int min_lines, int attach_lines, CarmenLoopSet* out, std::string* error) {
  const LaserGeometry geometry;
  std::vector<ScanPair> rel_pairs;
  if (!readCarmenLog(log_path, &out->log, error) ||
      !correctedSequence(out->log, corrected_csv, geometry, &out->scans, &out->ref, &out->odom,
                         &out->raw, error) ||
      !loopRelationPairs(out->log, relations_path, geometry, min_lines, &out->rel_scans, &rel_pairs,
                         error) ||
      !readRelations(relations_path, &out->relations, error))
    return false;
  const coral::Isometries corrected = out->ref;
  if (!relationGraph(LogNodes(out->log, out->raw), out->odom, out->relations, attach_lines,
                     &out->ref, &out->figures, error))
    return false;
  out->ate_reference_corrected = absoluteTrajectoryError(out->ref, corrected, 2);
  LoopCandidateConfig lookalike_only = cfg;
  lookalike_only.max_radius_candidates = 0;
  std::vector<LoopCandidate> registered;
  if (!buildLoopCandidates(out->scans, out->ref, out->odom, lookalike_only, &out->lookalikes,
                           error) ||
      !relationRegistrations(out->rel_scans, rel_pairs, cfg, &registered, error))
    return false;
  out->revisits.clear();
  for (const ScanPair& p : rel_pairs) {
    LoopCandidate c;
    c.a = p.a;
    c.b = p.b;
    c.source = "relation";
    c.T_a_b = c.T_ref = p.T_a_b;
    c.is_true = c.converged = true;
    out->revisits.push_back(c);
  }
  out->revisits.insert(out->revisits.end(), registered.begin(), registered.end());
  return true;
}

}  // namespace eval
}  // namespace coral_introspection
