// Scan pairing policy (no ROS master): consecutive, keyframe distance, time gap, resets.
#include <gtest/gtest.h>

#include "coral_introspection/online/pairing.hpp"

using namespace coral_introspection;
using online::PairAction;

TEST(Pairing, ConsecutiveByDefault) {
  online::ScanPairing p;
  EXPECT_EQ(p.offer(1.0, coral::Vec3::Zero()), PairAction::kFirst);
  EXPECT_EQ(p.offer(1.1, coral::Vec3::Zero()), PairAction::kPair);
  EXPECT_EQ(p.offer(1.2, coral::Vec3::Zero()), PairAction::kPair);
  EXPECT_DOUBLE_EQ(p.referenceStamp(), 1.2);
}

TEST(Pairing, KeyframeKeptUntilMinDistance) {
  online::PairingConfig c;
  c.min_distance = 1.0;
  c.max_time_gap = 0.0;  // no limit
  online::ScanPairing p(c);
  EXPECT_EQ(p.offer(0.0, coral::Vec3(0, 0, 0)), PairAction::kFirst);
  EXPECT_EQ(p.offer(0.1, coral::Vec3(0.4, 0, 0)), PairAction::kTooClose);
  EXPECT_EQ(p.offer(0.2, coral::Vec3(0.9, 0, 0)), PairAction::kTooClose);
  EXPECT_DOUBLE_EQ(p.referenceStamp(), 0.0);  // keyframe unchanged
  EXPECT_EQ(p.offer(0.3, coral::Vec3(1.1, 0, 0)), PairAction::kPair);
  EXPECT_EQ(p.offer(0.4, coral::Vec3(1.5, 0, 0)), PairAction::kTooClose);  // from new keyframe
}

TEST(Pairing, OldReferenceDropped) {
  online::PairingConfig c;
  c.max_time_gap = 0.5;
  online::ScanPairing p(c);
  p.offer(0.0, coral::Vec3::Zero());
  EXPECT_EQ(p.offer(0.6, coral::Vec3::Zero()), PairAction::kGapReset);
  EXPECT_EQ(p.offer(1.0, coral::Vec3::Zero()), PairAction::kPair);
}

TEST(Pairing, BackwardsAndDuplicateStampsReset) {
  online::ScanPairing p;
  p.offer(5.0, coral::Vec3::Zero());
  p.offer(5.1, coral::Vec3::Zero());
  EXPECT_EQ(p.offer(5.1, coral::Vec3::Zero()), PairAction::kDuplicateReset);
  EXPECT_EQ(p.offer(1.0, coral::Vec3::Zero()), PairAction::kBackwardsReset);  // bag looped
  EXPECT_EQ(p.offer(1.1, coral::Vec3::Zero()), PairAction::kPair);            // pairs again
}

TEST(Pairing, ConfigValidation) {
  online::PairingConfig c;
  EXPECT_EQ(c.validate(), "");
  c.min_distance = -1.0;
  EXPECT_NE(c.validate().find("pairing/min_distance"), std::string::npos);
}
