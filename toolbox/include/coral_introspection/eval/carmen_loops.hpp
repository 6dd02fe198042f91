// The loop-closure evaluation set of a CARMEN log with benchmark relations (Radish Intel,
// ACES), as coral_loop_eval and test_loop_closure build it:
//   - graph nodes: the scans with corrected poses (the logs' SLAM result), odometry: the raw
//     log between them;
//   - reference trajectory: the relation graph (log_nodes.hpp), not the corrected poses;
//   - revisits with exact labels: the benchmark relations joining scans more than
//     `min_lines` log lines apart, as they are (true) and registered again from a perturbed
//     pose (relationRegistrations: true or false against the relation);
//   - look-alike places: scans at least 8 m apart in the reference registered from four
//     headings (buildLoopCandidates; false).
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/eval/carmen_log.hpp"
#include "coral_introspection/eval/log_nodes.hpp"
#include "coral_introspection/eval/loop_candidates.hpp"

namespace coral_introspection {
namespace eval {

struct CarmenLoopSet {
  std::vector<CarmenLaserScan> log;
  std::vector<TrainingScan> scans;        // graph nodes
  coral::Isometries ref, odom;            // reference (relation graph) and odometry of the nodes
  std::vector<int> raw;                   // log line of each node
  std::vector<Relation> relations;        // every relation of the log
  RelationGraphFigures figures;           // the reference against the corrected poses
  double ate_reference_corrected = 0.0;   // [m] ATE between the two
  std::vector<LoopCandidate> lookalikes;  // a, b index `scans`
  std::vector<TrainingScan> rel_scans;    // the raw scans of the loop relations
  std::vector<LoopCandidate> revisits;  // relations, then their registrations; a, b index rel_scans
};

// cfg: evaluationCandidates(2, tolerance) or a reduced copy (its max_radius_candidates bounds
// the relations registered again; max_lookalike_pairs the look-alike pairs). min_lines: 30
// in the evaluation; attach_lines: how far (log lines) a raw scan may hang off a node (10).
bool loadCarmenLoopSet(const std::string& log_path, const std::string& corrected_csv,
                       const std::string& relations_path, const LoopCandidateConfig& cfg,
                       int min_lines, int attach_lines, CarmenLoopSet* out, std::string* error);

}  // namespace eval
}  // namespace coral_introspection
