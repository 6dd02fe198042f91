#include "coral_introspection/online/stream_checks.hpp"

#include <algorithm>

namespace coral_introspection {
namespace online {

bool BackwardsJump::offer(const std::string& key, double stamp) {
  auto it = newest_by_key_.find(key);
  const bool jump = it != newest_by_key_.end() && stamp < it->second - threshold_;
  if (jump) {
    reset();
    it = newest_by_key_.end();
  }
  if (it == newest_by_key_.end())
    newest_by_key_[key] = stamp;
  else
    it->second = std::max(it->second, stamp);
  newest_ = std::max(newest_, stamp);
  return jump;
}

void BackwardsJump::reset() {
  newest_by_key_.clear();
  newest_ = 0.0;
}

uint64_t SequenceGaps::offer(const std::string& source, uint32_t seq) {
  auto [it, first] = last_.emplace(source, seq);
  if (first) return 0;
  const uint32_t prev = it->second;
  it->second = seq;
  if (seq <= prev || seq - prev > max_gap_) return 0;  // not increasing, or a restart
  return seq - prev - 1;
}

}  // namespace online
}  // namespace coral_introspection
