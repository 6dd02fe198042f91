// Stream checks of the nodelet's input side: a looping bag is a backwards jump (small
// reorderings are not), and header.seq gaps count the messages lost upstream.
#include <gtest/gtest.h>

#include "coral_introspection/online/stream_checks.hpp"

using coral_introspection::online::BackwardsJump;
using coral_introspection::online::SequenceGaps;

TEST(BackwardsJump, LoopIsAJumpReorderingIsNot) {
  BackwardsJump j(1.0);
  EXPECT_FALSE(j.offer("radar", 100.0));
  EXPECT_FALSE(j.offer("radar", 100.5));
  EXPECT_FALSE(j.offer("radar", 100.2));  // 0.3 s out of order: not a jump
  EXPECT_DOUBLE_EQ(j.newest(), 100.5);
  EXPECT_FALSE(j.offer("imu", 50.0));   // another key has its own history
  EXPECT_TRUE(j.offer("radar", 90.0));  // the bag looped
  EXPECT_DOUBLE_EQ(j.newest(), 90.0);   // the old loop's stamps are forgotten
  EXPECT_FALSE(j.offer("imu", 50.5));   // ... for every key
  EXPECT_FALSE(j.offer("radar", 90.1));
  EXPECT_DOUBLE_EQ(j.newest(), 90.1);
}

TEST(BackwardsJump, ExactlyAtTheThresholdIsNotAJump) {
  BackwardsJump j(2.0);
  j.offer("a", 10.0);
  EXPECT_FALSE(j.offer("a", 8.0));
  EXPECT_TRUE(j.offer("a", 7.9));
}

TEST(SequenceGaps, CountsPlausibleGapsPerSource) {
  SequenceGaps g(100);
  EXPECT_EQ(g.offer("/velodyne", 5), 0u);  // first message of a source
  EXPECT_EQ(g.offer("/velodyne", 6), 0u);
  EXPECT_EQ(g.offer("/velodyne", 9), 2u);  // 7 and 8 lost
  EXPECT_EQ(g.offer("/other", 1), 0u);     // independent source
  EXPECT_EQ(g.offer("/velodyne", 10), 0u);
  EXPECT_EQ(g.offer("/velodyne", 0), 0u);    // publisher restarted / bag looped
  EXPECT_EQ(g.offer("/velodyne", 2), 1u);    // counting resumes after a restart
  EXPECT_EQ(g.offer("/velodyne", 500), 0u);  // gap > max_gap: a restart, not 397 losses
  EXPECT_EQ(g.offer("/other", 3), 1u);
}

TEST(SequenceGaps, UnsetSequenceNumbersCountNothing) {
  SequenceGaps g;
  for (int i = 0; i < 5; ++i) EXPECT_EQ(g.offer("/bag", 0), 0u);
}
