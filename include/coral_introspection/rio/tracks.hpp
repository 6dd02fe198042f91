// Radar point tracks and landmarks (the l_j of Eq. 1). A static point of a new frame is
// matched to a track by probability-guided one-to-one association (Sec. III-D, Eq. 13-14:
// highest density N(l; p_k, Sigma_k) within the 3-sigma gate, in the frame of the new
// point); unmatched points start tracks. A track with enough observations in the window
// becomes a landmark, a 3-D parameter block of the window problem (Sec. III-E). When a
// frame leaves the window its observations are dropped; a landmark left without any
// becomes a fixed map point (optional) that later frames can still be matched against.
#pragma once

#include <Eigen/Geometry>
#include <functional>
#include <map>
#include <vector>

#include "coral_introspection/rio/config.hpp"

namespace coral_introspection {
namespace rio {

struct Observation {
  long frame = -1;  // frame id
  Vec3 p;           // measured point, radar frame
  Mat3 W;           // whitening of its covariance (W^T W = Sigma_k^-1)
};

struct Track {
  std::vector<Observation> obs;  // in the window, oldest first
  Vec3 position = Vec3::Zero();  // world; the parameter block of a landmark
  bool landmark = false;         // has a block in the window problem
  bool fixed = false;            // map point: held constant
  long last_frame = -1;
};

using RadarPoseOf = std::function<Eigen::Isometry3d(long frame)>;  // T_world_radar

class Tracks {
 public:
  struct Stats {
    int matched = 0, created = 0, map_matched = 0;
  };
  // Associates the static points of `frame` (radar frame, covariances cov for the gate,
  // whitening W for the residuals) with the tracks, predicted into the frame's radar pose
  // T_world_radar. pose_of gives the current estimate of earlier frames.
  Stats associate(long frame, const Points& points, const coral::Covariances& cov,
                  const std::vector<Mat3>& W, const Eigen::Isometry3d& T_world_radar,
                  const RadarPoseOf& pose_of, const AssociationConfig& cfg);
  // Tracks with >= min_observations observations become landmarks, initialised at the
  // information-weighted mean of their observations in the world.
  void promote(int min_observations, const RadarPoseOf& pose_of);
  // Removes every observation of `frame`; see the header comment for what happens next.
  void dropFrame(long frame, const AssociationConfig& cfg);
  // Landmarks whose information went into the marginalisation prior: they become fixed
  // map points (AssociationConfig::map_landmarks) or are forgotten.
  void retire(const std::vector<long>& ids, const AssociationConfig& cfg);
  // Removes one observation (an outlier); a track left with too few stops being a landmark.
  void dropObservation(long track, long frame, int min_observations);
  void clear() { tracks_.clear(); }

  std::map<long, Track>& all() { return tracks_; }
  const std::map<long, Track>& all() const { return tracks_; }
  int numLandmarks() const;
  int numMapPoints() const;

 private:
  Vec3 worldPosition(const Track& t, const RadarPoseOf& pose_of) const;
  std::map<long, Track> tracks_;
  long next_id_ = 0;
};

}  // namespace rio
}  // namespace coral_introspection
