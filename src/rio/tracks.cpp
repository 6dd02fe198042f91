#include "coral_introspection/rio/tracks.hpp"

#include <Eigen/Cholesky>
#include <algorithm>

#include "coral_introspection/radar/probabilistic_association.hpp"

namespace coral_introspection {
namespace rio {

Vec3 Tracks::worldPosition(const Track& t, const RadarPoseOf& pose_of) const {
  if (t.landmark || t.fixed || t.obs.empty()) return t.position;
  const Observation& last = t.obs.back();
  return pose_of(last.frame) * last.p;
}

Tracks::Stats Tracks::associate(long frame, const Points& points, const coral::Covariances& cov,
                                const std::vector<Mat3>& W, const Eigen::Isometry3d& T_world_radar,
                                const RadarPoseOf& pose_of, const AssociationConfig& cfg) {
  Stats stats;
  // Candidates: every track, predicted into the new radar frame (Eq. 13 is evaluated
  // there, where Sigma_k of the new point lives).
  const Eigen::Isometry3d T_radar_world = T_world_radar.inverse();
  std::vector<long> ids;
  Points candidates;
  for (const auto& [id, t] : tracks_) {
    const Vec3 l = T_radar_world * worldPosition(t, pose_of);
    if (t.fixed && l.norm() > 100.0) continue;  // far map points cannot match
    ids.push_back(id);
    candidates.push_back(l);
  }
  radar::ProbabilisticAssociationConfig acfg;
  acfg.dimension = 3;
  acfg.gate_sigma = cfg.gate_sigma;
  acfg.max_search_radius = cfg.max_search_radius;
  std::string err;
  const std::vector<radar::ProbabilisticMatch> matches =
      radar::associateOneToOne(points, cov, candidates, acfg, &err);
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Observation o{frame, points[k], W[k]};
    if (k < matches.size() && matches[k].target >= 0) {
      Track& t = tracks_[ids[matches[k].target]];
      stats.map_matched += t.fixed && t.obs.empty();
      t.obs.push_back(o);
      t.last_frame = frame;
      ++stats.matched;
    } else {
      Track t;
      t.obs.push_back(o);
      t.last_frame = frame;
      tracks_.emplace(next_id_++, std::move(t));
      ++stats.created;
    }
  }
  return stats;
}

void Tracks::promote(int min_observations, const RadarPoseOf& pose_of) {
  for (auto& [id, t] : tracks_) {
    if (t.landmark || t.fixed || static_cast<int>(t.obs.size()) < min_observations) continue;
    // l = (sum Omega_i)^-1 sum Omega_i x_i, Omega_i = R W^T W R^T (world information).
    Mat3 info = Mat3::Zero();
    Vec3 rhs = Vec3::Zero();
    for (const Observation& o : t.obs) {
      const Eigen::Isometry3d T = pose_of(o.frame);
      const Mat3 R = T.linear();
      const Mat3 omega = R * o.W.transpose() * o.W * R.transpose();
      info += omega;
      rhs += omega * (T * o.p);
    }
    t.position = info.ldlt().solve(rhs);
    t.landmark = true;
  }
}

void Tracks::dropFrame(long frame, const AssociationConfig& cfg) {
  for (auto it = tracks_.begin(); it != tracks_.end();) {
    Track& t = it->second;
    t.obs.erase(std::remove_if(t.obs.begin(), t.obs.end(),
                               [frame](const Observation& o) { return o.frame == frame; }),
                t.obs.end());
    if (t.obs.empty() && !(cfg.map_landmarks && (t.landmark || t.fixed))) {
      it = tracks_.erase(it);
      continue;
    }
    if (t.obs.empty()) t.fixed = true, t.landmark = false;
    ++it;
  }
  // Bound the map: forget the map points seen longest ago.
  int n_map = numMapPoints();
  for (auto it = tracks_.begin(); n_map > cfg.max_map_landmarks && it != tracks_.end();) {
    if (it->second.fixed && it->second.obs.empty()) {
      it = tracks_.erase(it);
      --n_map;
    } else {
      ++it;
    }
  }
}

void Tracks::retire(const std::vector<long>& ids, const AssociationConfig& cfg) {
  for (long id : ids) {
    auto it = tracks_.find(id);
    if (it == tracks_.end()) continue;
    if (!cfg.map_landmarks) {
      tracks_.erase(it);
      continue;
    }
    it->second.obs.clear();
    it->second.landmark = false;
    it->second.fixed = true;
  }
}

void Tracks::dropObservation(long track, long frame, int min_observations) {
  auto it = tracks_.find(track);
  if (it == tracks_.end()) return;
  Track& t = it->second;
  t.obs.erase(std::remove_if(t.obs.begin(), t.obs.end(),
                             [frame](const Observation& o) { return o.frame == frame; }),
              t.obs.end());
  if (!t.fixed && static_cast<int>(t.obs.size()) < min_observations) t.landmark = false;
  if (t.obs.empty() && !t.fixed) tracks_.erase(it);
}

int Tracks::numLandmarks() const {
  int n = 0;
  for (const auto& [id, t] : tracks_) n += t.landmark;
  return n;
}

int Tracks::numMapPoints() const {
  int n = 0;
  for (const auto& [id, t] : tracks_) n += t.fixed && t.obs.empty();
  return n;
}

}  // namespace rio
}  // namespace coral_introspection
