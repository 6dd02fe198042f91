// Small checks on an incoming message stream, ROS-free so they are unit-tested alone:
// time jumping backwards (a looping bag, a restarted simulation) and messages missing
// upstream (sequence-number gaps).
#pragma once

#include <cstdint>
#include <map>
#include <string>

namespace coral_introspection {
namespace online {

// A stamp stream jumping backwards: per key (e.g. a TF child frame), a stamp more than
// threshold [s] older than the newest stamp of that key. Small reorderings (<= threshold)
// are normal (several publishers, transport) and are not jumps.
class BackwardsJump {
 public:
  explicit BackwardsJump(double threshold_s = 1.0) : threshold_(threshold_s) {}
  // True when `stamp` jumps back for `key`; then every key's history is forgotten (the
  // stream restarted). The stamp becomes the newest of its key either way.
  bool offer(const std::string& key, double stamp);
  double newest() const { return newest_; }  // [s] over all keys since the last jump; 0 before
  void reset();

 private:
  double threshold_;
  double newest_ = 0.0;
  std::map<std::string, double> newest_by_key_;
};

// Messages missing upstream of the subscriber (publisher queue, transport, subscriber queue,
// or the recording itself), from gaps in a per-source sequence number (ROS header.seq).
// A source whose numbers do not increase (always 0, restarted, looping bag) or jump by more
// than max_gap (a restart) counts nothing: only plausible gaps are counted.
class SequenceGaps {
 public:
  explicit SequenceGaps(uint32_t max_gap = 1000) : max_gap_(max_gap) {}
  // Number of messages missing between the previous message of `source` and this one.
  uint64_t offer(const std::string& source, uint32_t seq);

 private:
  uint32_t max_gap_;
  std::map<std::string, uint32_t> last_;
};

}  // namespace online
}  // namespace coral_introspection
