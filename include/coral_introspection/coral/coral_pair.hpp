// CorAl of one scan pair at many relative poses (the relative check probes 1 + 2 x axes
// poses per pair, training many more). Everything that does not depend on the pose is done
// once: input hygiene and the voxel filter (b in its own sensor frame), one neighbour grid
// per scan, the query subset, and each query's neighbourhood in its own cloud. Per pose
// only each query's neighbourhood in the other cloud is searched, in that cloud's own grid:
// the query is moved into the other cloud's frame (distances are invariant under the rigid
// motion) and the neighbours' moments are rotated back into the query's frame.
//
// The same queries are scored at every pose (common random numbers), so Q differences
// between nearby poses carry no sampling or voxelisation noise of their own.
#pragma once

#include <memory>
#include <vector>

#include "coral_introspection/coral/coral.hpp"

namespace coral_introspection {
namespace coral {

class CoralPair {
 public:
  // a in the common frame; b in its own sensor frame (b.origin in that frame), moved by the
  // pose given to evaluate(). probe_queries > 0: evaluateProbe() and evaluate()'s `probe`
  // score a systematic sub-sample of at most this many of each scan's queries (0 = all).
  // Precondition: cfg.validate() is empty. 2D (cfg.dimension 2): poses are rotations about z.
  CoralPair(const Scan& a, const Scan& b, const CoralConfig& cfg, int probe_queries = 0);
  ~CoralPair();
  CoralPair(const CoralPair&) = delete;
  CoralPair& operator=(const CoralPair&) = delete;

  // CorAl of a and b moved by T_a_b, every query (per_point as cfg says, positions in a's
  // frame). The same result as computeCoral(a, transformScan(b', T_a_b)) for b' = b after
  // hygiene and voxel filter in its own frame, up to the summation order of the moments
  // (and b's query subset, drawn in b's frame). With `probe`, also the aggregate over the
  // probe queries of the same evaluation. per_point false: no per-point entropies whatever
  // cfg.per_point says (extra poses of a pair whose verdict publishes them).
  CoralResult evaluate(const Eigen::Isometry3d& T_a_b, CoralResult* probe = nullptr,
                       bool per_point = true) const;
  // The aggregate over the probe queries only (no per-point entropies).
  CoralResult evaluateProbe(const Eigen::Isometry3d& T_a_b) const;
  const CoralConfig& config() const;
  // The filtered points of a (side 0, a's frame) or b (side 1, b's own frame), empty when
  // the pair was refused, and that scan's sensor origin in the same frame (Scan::origin):
  // what the free-space check (free_space.hpp) casts its rays from.
  const Points& points(int side) const;
  const Vec3& origin(int side) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace coral
}  // namespace coral_introspection
