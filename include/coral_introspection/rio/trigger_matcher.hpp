// Radar measurement time from a trigger topic: a scan whose header carries no usable
// stamp (the TI mmWave driver's zero stamps) gets the stamp of the trigger with the same
// sequence number (plus a configurable offset). Scans wait for their trigger; waiting
// scans and unused triggers are bounded. ROS-free (the adapters pass seq and stamps).
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
  long dropped() const { return dropped_; }  // scans that never got a trigger
  void clear();

 private:
  long seq_offset_;
  std::size_t capacity_;
  std::map<long, double> triggers_;  // seq -> stamp
  std::deque<std::pair<long, RadarFrame>> waiting_;
  long dropped_ = 0;
};

}  // namespace rio
}  // namespace coral_introspection
