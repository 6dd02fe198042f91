// Radar measurement time from a trigger topic: a scan whose header carries no usable
// stamp (the TI mmWave driver's zero stamps) gets the stamp of the trigger with the same
// sequence number (plus a configurable offset). Scans wait for their trigger; waiting
// scans and unused triggers are bounded (the lowest sequence numbers go first).
// Sequence restarts: a trigger (or scan) whose seq is below the previous one's starts a new
// sequence (a bag played in a loop, a restarted driver). The stored triggers and waiting
// scans of the old one are dropped (scans counted in dropped()): kept, the old triggers' higher
// numbers would outlive every new trigger (each evicted on arrival) and the new scans would
// never find theirs, or a new scan would take an old trigger's stamp. Whichever of the two
// streams restarts first drops the old sequence's entries of both; the other keeps what the
// new sequence already gave. ROS-free (the adapters pass seq and stamps).
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <vector>

#include "coral_introspection/rio/types.hpp"

namespace coral_introspection {
namespace rio {

class TriggerMatcher {
 public:
  // trigger seq = scan seq + seq_offset. capacity bounds stored triggers and waiting scans.
  explicit TriggerMatcher(long seq_offset = 0, std::size_t capacity = 64)
      : seq_offset_(seq_offset), capacity_(capacity) {}

  // A trigger; returns the waiting scans it completes (stamped, in arrival order).
  std::vector<RadarFrame> addTrigger(std::uint32_t seq, double stamp);
  // A scan; returned at once (stamped) when its trigger is known, else it waits.
  std::vector<RadarFrame> addScan(std::uint32_t seq, RadarFrame frame);

  std::size_t waiting() const { return waiting_.size(); }
  long dropped() const { return dropped_; }         // scans that never got a trigger
  long restarts() const { return trigger_epoch_; }  // trigger sequence restarts
  void clear();

 private:
  void dropWaiting();

  long seq_offset_;
  std::size_t capacity_;
  std::map<long, double> triggers_;  // seq -> stamp
  std::deque<std::pair<long, RadarFrame>> waiting_;
  long dropped_ = 0;
  // Newest seq of each stream (-1: none yet) and how often each restarted.
  long last_trigger_seq_ = -1, last_scan_seq_ = -1;
  long trigger_epoch_ = 0, scan_epoch_ = 0;
};

}  // namespace rio
}  // namespace coral_introspection
