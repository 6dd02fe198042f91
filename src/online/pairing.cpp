#include "coral_introspection/online/pairing.hpp"

#include <cmath>
#include <sstream>

namespace coral_introspection {
namespace online {

std::string PairingConfig::validate() const {
  std::ostringstream e;
  if (!(min_distance >= 0.0 && std::isfinite(min_distance)))
    e << "pairing/min_distance must be >= 0 m (got " << min_distance << ")";
  if (!(max_time_gap >= 0.0 && std::isfinite(max_time_gap))) {
    if (!e.str().empty()) e << "; ";
    e << "pairing/max_time_gap must be >= 0 s (got " << max_time_gap << ")";
  }
  return e.str();
}

PairAction ScanPairing::offer(double stamp, const coral::Vec3& position) {
  PairAction a = PairAction::kPair;
  if (!has_reference_) {
    a = PairAction::kFirst;
  } else if (stamp < ref_stamp_) {
    a = PairAction::kBackwardsReset;
  } else if (stamp == ref_stamp_) {
    a = PairAction::kDuplicateReset;
  } else if (cfg_.max_time_gap > 0.0 && stamp - ref_stamp_ > cfg_.max_time_gap) {
    a = PairAction::kGapReset;
  } else if (cfg_.min_distance > 0.0 && (position - ref_position_).norm() < cfg_.min_distance) {
    return PairAction::kTooClose;  // keyframe stays
  }
  has_reference_ = true;
  ref_stamp_ = stamp;
  ref_position_ = position;
  return a;
}

}  // namespace online
}  // namespace coral_introspection
