// Induced misalignments are exactly the requested offsets in the later scan's frame.
#include <gtest/gtest.h>

#include <cmath>

#include "coral_introspection/coral/types.hpp"
#include "coral_introspection/eval/perturbation.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::eval;

TEST(Perturbation, RadarProtocolHasFourTranslationsPerMagnitude) {
  const auto ps = makePerturbations(PerturbationConfig::radarProtocol());
  ASSERT_EQ(ps.size(), 12u);
  EXPECT_EQ(ps[0].name, "forward");
  EXPECT_EQ(ps[0].group, "0.3 m");
  EXPECT_DOUBLE_EQ(ps[0].dx, 0.3);
  EXPECT_DOUBLE_EQ(ps[1].dx, -0.3);
  EXPECT_DOUBLE_EQ(ps[2].dy, 0.3);   // left = +y
  EXPECT_DOUBLE_EQ(ps[3].dy, -0.3);  // right = -y
  EXPECT_EQ(ps[11].group, "0.7 m");
  for (const auto& p : ps) EXPECT_DOUBLE_EQ(p.dyaw, 0.0);
}

TEST(Perturbation, OffsetIsExactInTheLaterScansFrame) {
  // A rotated, translated pair: the offset must appear in b's axes, not in a's.
  const Eigen::Isometry3d T_a_b = se2(4.0, -1.0, 0.7);
  for (const Perturbation& p : makePerturbations(PerturbationConfig::radarProtocol())) {
    const Eigen::Isometry3d T_a_b2 = perturb(T_a_b, p);
    // The perturbed sensor origin, expressed in the true b frame, is (dx, dy).
    const Vec3 o = T_a_b.inverse() * (T_a_b2 * Vec3::Zero());
    EXPECT_NEAR(o.x(), p.dx, 1e-12) << p.name;
    EXPECT_NEAR(o.y(), p.dy, 1e-12) << p.name;
    EXPECT_NEAR(o.z(), 0.0, 1e-12);
    // Every point of b moves by the same offset in b's frame (pure translation).
    const Vec3 q(10.0, 3.0, 0.0);
    const Vec3 moved = T_a_b.inverse() * (T_a_b2 * q) - q;
    EXPECT_NEAR((moved - Vec3(p.dx, p.dy, 0.0)).norm(), 0.0, 1e-12);
    // Its length in a's frame is the magnitude (the pair's rotation does not scale it).
    EXPECT_NEAR((T_a_b2.translation() - T_a_b.translation()).norm(), std::hypot(p.dx, p.dy), 1e-12);
  }
}

TEST(Perturbation, LidarProtocolCombinesTranslationAndYaw) {
  const auto ps = makePerturbations(PerturbationConfig::lidarProtocol());
  ASSERT_EQ(ps.size(), 4u);
  EXPECT_EQ(ps[0].group, "0.1 m + 0.1 rad");
  const Eigen::Isometry3d T_a_b = se2(1.0, 2.0, -0.3);
  for (const auto& p : ps) {
    EXPECT_DOUBLE_EQ(std::abs(p.dyaw), 0.1);
    const Eigen::Isometry3d D = T_a_b.inverse() * perturb(T_a_b, p);  // = Delta in b's frame
    EXPECT_NEAR(yawOf(D.linear()), p.dyaw, 1e-12);
    EXPECT_NEAR(D.translation().head<2>().norm(), 0.1, 1e-12);
    // A point 10 m ahead of b is displaced by the yaw about b's origin plus the offset.
    const Vec3 q(10.0, 0.0, 0.0);
    const Vec3 expected =
        Vec3(p.dx, p.dy, 0) + Vec3(10 * std::cos(p.dyaw), 10 * std::sin(p.dyaw), 0);
    EXPECT_NEAR((T_a_b.inverse() * (perturb(T_a_b, p) * q) - expected).norm(), 0.0, 1e-12);
  }
}

TEST(Perturbation, RotationGroupsAndValidation) {
  PerturbationConfig c;
  c.translations.clear();
  c.rotations = {0.05};
  const auto ps = makePerturbations(c);
  ASSERT_EQ(ps.size(), 2u);
  EXPECT_EQ(ps[0].group, "0.05 rad");
  EXPECT_DOUBLE_EQ(ps[1].dyaw, -0.05);
  c.rotations.clear();
  EXPECT_FALSE(c.validate().empty());
  c.translations = {-0.3};
  EXPECT_NE(c.validate().find("translations"), std::string::npos);
}
