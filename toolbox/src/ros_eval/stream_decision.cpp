#include "coral_introspection/ros_eval/stream_decision.hpp"

#include "coral_introspection/online/introspector.hpp"

namespace coral_introspection {
namespace ros_eval {

eval::LoopDecision streamVerdictDecision(const std::vector<eval::TrainingScan>& scans,
                                         const online::IntrospectorConfig& cfg) {
  return [&scans, cfg](const eval::LoopCandidate& c, Eigen::Isometry3d*) {
    const online::PairJudgement j =
        online::judgePair(scans[c.a].scan, scans[c.b].scan, c.T_a_b, cfg, false);
    return j.verdict.valid && j.verdict.aligned;
  };
}

}  // namespace ros_eval
}  // namespace coral_introspection
