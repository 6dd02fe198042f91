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
  EXPECT_EQ(box.noticesLost(), 1u);
  EXPECT_EQ(box.dropped(), 0u);  // no scan was replaced
  EXPECT_EQ(box.take(), 2);
  EXPECT_EQ(box.take(), 3);
}

// A replaced scan leaves its notice in place: the taker sees every scan in arrival order,
// the dropped ones as notices (here: negated).
TEST(Mailbox, DroppedScanLeavesANoticeInOrder) {
  Mailbox<int> box(10, [](const int& scan) { return -scan; });
  box.put(1, true);
  box.put(2, true);  // 1 -> notice -1
  box.put(3, true);  // 2 -> notice -2
  box.put(100, false);
  EXPECT_EQ(box.dropped(), 2u);
  EXPECT_EQ(box.take(), -1);
  EXPECT_EQ(box.take(), -2);
  EXPECT_EQ(box.take(), 3);
  EXPECT_EQ(box.take(), 100);
  EXPECT_EQ(box.noticesLost(), 0u);
}

// Drop notices count against the bound too: a flood of scans keeps memory bounded.
TEST(Mailbox, DropNoticesAreBounded) {
  Mailbox<int> box(3, [](const int& scan) { return -scan; });
  for (int i = 1; i <= 10; ++i) box.put(i, true);
  EXPECT_EQ(box.dropped(), 9u);
  EXPECT_EQ(box.noticesLost(), 6u);  // notices -1 .. -6
  EXPECT_EQ(box.take(), -7);
  EXPECT_EQ(box.take(), -8);
  EXPECT_EQ(box.take(), -9);
  EXPECT_EQ(box.take(), 10);
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

// Two scans in a burst (a looping bag restarting) while the worker is idle: the first is
// handed to it, the second waits, nothing is dropped. Once the worker is busy, a newer scan
// replaces the waiting one (counted).
TEST(Mailbox, BurstWhileTheTakerIsIdleDropsNothing) {
  Mailbox<int> box;
  std::atomic<int> first{-1}, second{-1};
  std::atomic<bool> go{false};
  std::thread worker([&] {
    first = box.take().value_or(0);
    while (!go.load()) std::this_thread::yield();  // busy with `first`
    second = box.take().value_or(0);
  });
  while (box.idleTakers() == 0) std::this_thread::yield();
  box.put(1, true);  // handed to the idle worker (even before it runs)
  box.put(2, true);  // microseconds later
  EXPECT_EQ(box.dropped(), 0u) << "scan 1 was handed to an idle worker";
  while (first.load() < 0) std::this_thread::yield();
  EXPECT_EQ(first.load(), 1);
  box.put(3, true);  // the worker is busy: 3 replaces 2
  EXPECT_EQ(box.dropped(), 1u);
  go = true;
  worker.join();
  EXPECT_EQ(second.load(), 3);
}
