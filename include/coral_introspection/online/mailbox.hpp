// Hand-over between the threads that receive scans and the one thread that judges them.
// "Newest wins": a droppable item (a scan) replaces the droppable item still waiting, which
// is counted as dropped, so a slow judge skips scans instead of falling behind. Items that
// are not droppable (small notices such as a TF failure) queue in order, up to a bound.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>

namespace coral_introspection {
namespace online {

template <class T>
class Mailbox {
 public:
  explicit Mailbox(std::size_t max_notices = 100) : max_notices_(max_notices) {}

  // Returns false when closed (the item is discarded).
  bool put(T item, bool droppable) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (closed_) return false;
      for (auto it = items_.begin(); it != items_.end(); ++it)
        if (it->droppable == droppable && (droppable || notices_ >= max_notices_)) {
          items_.erase(it);  // the older scan (or, when full, the oldest notice)
          ++dropped_;
          if (!droppable) --notices_;
          break;
        }
      items_.push_back({std::move(item), droppable});
      if (!droppable) ++notices_;
    }
    cv_.notify_one();
    return true;
  }

  // Blocks until an item is available (oldest first) or the mailbox is closed (nullopt).
  std::optional<T> take() {
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait(lock, [this] { return closed_ || !items_.empty(); });
    if (closed_) return std::nullopt;
    Entry e = std::move(items_.front());
    items_.pop_front();
    if (!e.droppable) --notices_;
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

  uint64_t dropped() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return dropped_;
  }

 private:
  struct Entry {
    T item;
    bool droppable;
  };
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<Entry> items_;
  std::size_t max_notices_, notices_ = 0;
  uint64_t dropped_ = 0;
  bool closed_ = false;
};

}  // namespace online
}  // namespace coral_introspection
