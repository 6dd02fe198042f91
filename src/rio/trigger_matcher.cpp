#include "coral_introspection/rio/trigger_matcher.hpp"

namespace coral_introspection {
namespace rio {

void TriggerMatcher::clear() {
  triggers_.clear();
  waiting_.clear();
}

void TriggerMatcher::dropWaiting() {
  dropped_ += static_cast<long>(waiting_.size());
  waiting_.clear();
}

std::vector<RadarFrame> TriggerMatcher::addTrigger(std::uint32_t seq, double stamp) {
  const long s = static_cast<long>(seq);
  if (s < last_trigger_seq_) {  // a new sequence: no stored trigger belongs to it
    ++trigger_epoch_;
    triggers_.clear();
    if (trigger_epoch_ > scan_epoch_) dropWaiting();  // the scans have not restarted yet
  }
  last_trigger_seq_ = s;
  triggers_[s] = stamp;
  while (triggers_.size() > capacity_) triggers_.erase(triggers_.begin());
  std::vector<RadarFrame> ready;
  for (auto it = waiting_.begin(); it != waiting_.end();) {
    auto t = triggers_.find(it->first + seq_offset_);
    if (t == triggers_.end()) {
      ++it;
      continue;
    }
    it->second.t = t->second;
    ready.push_back(std::move(it->second));
    it = waiting_.erase(it);
  }
  return ready;
}

std::vector<RadarFrame> TriggerMatcher::addScan(std::uint32_t seq, RadarFrame frame) {
  const long s = static_cast<long>(seq);
  if (s < last_scan_seq_) {  // a new sequence: no waiting scan belongs to it
    ++scan_epoch_;
    dropWaiting();
    if (scan_epoch_ > trigger_epoch_) triggers_.clear();  // the triggers have not restarted yet
  }
  last_scan_seq_ = s;
  auto t = triggers_.find(s + seq_offset_);
  if (t != triggers_.end()) {
    frame.t = t->second;
    return {std::move(frame)};
  }
  waiting_.emplace_back(s, std::move(frame));
  while (waiting_.size() > capacity_) {
    waiting_.pop_front();
    ++dropped_;
  }
  return {};
}

}  // namespace rio
}  // namespace coral_introspection
