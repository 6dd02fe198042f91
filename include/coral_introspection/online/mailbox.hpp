// Hand-over between the threads that receive scans and the one thread that judges them.
// "Newest wins": a droppable item (a scan) replaces the droppable item still waiting, which
// is counted as dropped, so a slow judge skips scans instead of falling behind. Items that
// are not droppable (small notices such as a TF failure) queue in order, up to a bound.
// With a drop_notice function, a replaced scan leaves a notice in its place (e.g. "dropped:
// worker busy"), so the taker still learns about every scan, in arrival order.
// A scan put while a taker is idle in take() is handed to it and never replaced: a burst of
// two scans within microseconds (a looping bag restarting) costs no scan while the taker is
// only not yet scheduled; scans are dropped only while the taker is busy.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>

namespace coral_introspection {
namespace online {

template <class T>
class Mailbox {
 public:
  // drop_notice(scan): the notice that replaces a dropped scan (none when empty).
  explicit Mailbox(std::size_t max_notices = 100, std::function<T(const T&)> drop_notice = {})
      : max_notices_(max_notices), drop_notice_(std::move(drop_notice)) {}

  // Returns false when closed (the item is discarded).
  bool put(T item, bool droppable) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (closed_) return false;
      if (droppable) {
        for (auto it = items_.begin(); it != items_.end(); ++it) {
          if (!it->droppable || it->handed) continue;
          ++dropped_;  // at most one scan waits: the older one is never judged
          if (drop_notice_) {
            it->item = drop_notice_(it->item);
            it->droppable = false;
            ++notices_;
          } else {
            items_.erase(it);
          }
          break;
        }
      }
      // Bounded notices: the oldest notice goes (counted). max_notices >= 1.
      const std::size_t incoming = droppable ? 0 : 1;
      while (notices_ + incoming > max_notices_ && notices_ > 0) eraseOldestNotice();
      const bool handed = droppable && idle_takers_ > handed_;  // an idle taker will get it
      items_.push_back({std::move(item), droppable, handed});
      if (!droppable) ++notices_;
      if (handed) ++handed_;
    }
    cv_.notify_one();
    return true;
  }

  // Blocks until an item is available (oldest first) or the mailbox is closed (nullopt).
  std::optional<T> take() {
    std::unique_lock<std::mutex> lock(mutex_);
    ++idle_takers_;
    cv_.wait(lock, [this] { return closed_ || !items_.empty(); });
    --idle_takers_;
    if (closed_) return std::nullopt;
    Entry e = std::move(items_.front());
    items_.pop_front();
    if (!e.droppable) --notices_;
    if (e.handed) --handed_;
    return std::move(e.item);
  }

  // Wakes take() for good; later puts are refused.
  void close() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closed_ = true;
      items_.clear();
    }
    cv_.notify_all();
  }

  uint64_t dropped() const {  // scans replaced by a newer scan before they were taken
    std::lock_guard<std::mutex> lock(mutex_);
    return dropped_;
  }
  std::size_t idleTakers() const {  // takers blocked in take()
    std::lock_guard<std::mutex> lock(mutex_);
    return idle_takers_;
  }
  uint64_t noticesLost() const {  // notices discarded because max_notices were waiting
    std::lock_guard<std::mutex> lock(mutex_);
    return notices_lost_;
  }

 private:
  void eraseOldestNotice() {
    for (auto it = items_.begin(); it != items_.end(); ++it)
      if (!it->droppable) {
        items_.erase(it);
        --notices_;
        ++notices_lost_;
        return;
      }
  }
  struct Entry {
    T item;
    bool droppable;
    bool handed = false;  // promised to an idle taker: not replaced
  };
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<Entry> items_;
  std::size_t max_notices_, notices_ = 0;
  std::size_t idle_takers_ = 0, handed_ = 0;  // takers in take(); waiting items handed to them
  std::function<T(const T&)> drop_notice_;
  uint64_t dropped_ = 0, notices_lost_ = 0;
  bool closed_ = false;
};

}  // namespace online
}  // namespace coral_introspection
