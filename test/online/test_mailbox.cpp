// The hand-over between the receiving threads and the nodelet's worker: the newest scan
// wins (the replaced one is counted), notices queue in order, close() wakes the worker.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "coral_introspection/online/mailbox.hpp"

using coral_introspection::online::Mailbox;

TEST(Mailbox, NewestScanWinsAndNoticesQueue) {
  Mailbox<int> box;
  EXPECT_TRUE(box.put(1, true));
  EXPECT_TRUE(box.put(100, false));  // a notice (e.g. a TF failure)
  EXPECT_TRUE(box.put(2, true));     // replaces scan 1, which was never judged
  EXPECT_TRUE(box.put(101, false));
  EXPECT_EQ(box.dropped(), 1u);
  EXPECT_EQ(box.take(), 100);
  EXPECT_EQ(box.take(), 2);
  EXPECT_EQ(box.take(), 101);
  EXPECT_TRUE(box.put(3, true));  // nothing waiting: nothing dropped
  EXPECT_EQ(box.take(), 3);
  EXPECT_EQ(box.dropped(), 1u);
}

TEST(Mailbox, NoticesAreBoundedOldestDropped) {
  Mailbox<int> box(2);
  box.put(1, false);
  box.put(2, false);
  box.put(3, false);
  EXPECT_EQ(box.dropped(), 1u);
  EXPECT_EQ(box.take(), 2);
  EXPECT_EQ(box.take(), 3);
}

TEST(Mailbox, CloseWakesABlockedTakerAndRefusesPuts) {
  Mailbox<int> box;
  std::optional<int> got = 7;
  std::thread taker([&] { got = box.take(); });
  box.close();
  taker.join();
  EXPECT_FALSE(got.has_value());
  EXPECT_FALSE(box.put(1, true));
}

TEST(Mailbox, WorkerSeesEveryScanWhenFastEnough) {
  Mailbox<int> box;
  std::atomic<int> taken{0};
  std::thread worker([&] {
    while (auto v = box.take()) taken = *v + 1;
  });
  for (int i = 0; i < 50; ++i) {
    box.put(i, true);
    while (taken.load() < i + 1) std::this_thread::yield();  // lock step: taken before the next
  }
  box.close();
  worker.join();
  EXPECT_EQ(box.dropped(), 0u);
  EXPECT_EQ(taken.load(), 50);
}
