// Which scan a new scan is compared with: the previous scan, or a keyframe that is kept
// until the sensor has travelled pairing/min_distance. ROS-free so it is unit-tested alone.
#pragma once

#include <string>

#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace online {

struct PairingConfig {
  double min_distance = 0.0;     // [m] travel from the reference before pairing; 0 = consecutive
  double max_time_gap = 1.0;     // [s] an older reference is dropped; 0 = no limit
  std::string validate() const;  // empty when valid
};

enum class PairAction {
  kFirst,           // no reference yet: the scan becomes the reference
  kPair,            // compare (reference, scan), then the scan becomes the reference
  kTooClose,        // travelled less than min_distance: scan dropped, reference kept
  kGapReset,        // reference older than max_time_gap: scan becomes the reference
  kBackwardsReset,  // stamp earlier than the reference (looping bag): reset
  kDuplicateReset,  // same stamp as the reference: reset
};

class ScanPairing {
 public:
  explicit ScanPairing(const PairingConfig& cfg = PairingConfig()) : cfg_(cfg) {}
  void setConfig(const PairingConfig& cfg) { cfg_ = cfg; }
  // Decides what to do with a scan at `stamp` [s] whose sensor is at `position` (fixed
  // frame), and updates the reference accordingly (kept only on kTooClose).
  PairAction offer(double stamp, const coral::Vec3& position);
  void reset() { has_reference_ = false; }
  double referenceStamp() const { return ref_stamp_; }  // [s], 0 before the first scan

 private:
  PairingConfig cfg_;
  bool has_reference_ = false;
  double ref_stamp_ = 0.0;
  coral::Vec3 ref_position_ = coral::Vec3::Zero();
};

}  // namespace online
}  // namespace coral_introspection
