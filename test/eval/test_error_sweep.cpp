// eval::sweepErrors: the errors coral_error_sweep and test_preset_verdicts judge.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "coral_introspection/coral/refinement.hpp"
#include "coral_introspection/coral/types.hpp"
#include "coral_introspection/eval/error_sweep.hpp"

using namespace coral_introspection;

namespace {

double yawDeg(const Eigen::Isometry3d& d) { return coral::yawOf(d.linear()) * 180.0 / M_PI; }

}  // namespace

// Errors between the default steps (coral_error_sweep --multiples / --yaw_deg): k tolerances
// along x, y and yaw both ways, then the fixed yaw angles both ways (180 once), angles below
// the rotation tolerance left out.
TEST(ErrorSweep, MultiplesAndYawAnglesOffTheDefaultGrid) {
  const coral::ToleranceConfig tol{0.3, 2.0};
  const auto errors = eval::sweepErrors(tol, 2, {1.5}, {1.0, 30.0, 180.0});
  ASSERT_EQ(errors.size(), 1u + 6u + 2u + 1u);
  EXPECT_TRUE(errors[0].ground_truth);
  EXPECT_TRUE(errors[0].delta.isApprox(Eigen::Isometry3d::Identity()));
  int x = 0, yaw30 = 0, yaw180 = 0;
  for (std::size_t i = 1; i < errors.size(); ++i) {
    const eval::SweepError& e = errors[i];
    EXPECT_FALSE(e.ground_truth) << e.label;
    if (e.axis == coral::Axis::kX) {
      ++x;
      EXPECT_DOUBLE_EQ(e.multiple, 1.5);
      EXPECT_NEAR(e.delta.translation().x(), e.sign * 0.45, 1e-12) << e.label;
    }
    if (e.label == "yaw+30deg" || e.label == "yaw-30deg") {
      ++yaw30;
      EXPECT_NEAR(yawDeg(e.delta), e.sign * 30.0, 1e-9) << e.label;
      EXPECT_NEAR(e.delta.translation().norm(), 0.0, 1e-12);
    }
    if (e.label.find("180deg") != std::string::npos) {
      ++yaw180;
      EXPECT_NEAR(std::abs(yawDeg(e.delta)), 180.0, 1e-9);
    }
    EXPECT_EQ(e.label.find("yaw+1deg"), std::string::npos) << "below the rotation tolerance";
  }
  EXPECT_EQ(x, 2);
  EXPECT_EQ(yaw30, 2);
  EXPECT_EQ(yaw180, 1);
  // The defaults are the grid of the doc's tables.
  EXPECT_EQ(eval::sweepErrors(tol, 2).size(), 1u + 4u * 6u + 9u);
}

// "Any rotation" (coral_error_sweep --turn_axes): the fixed angles about roll, pitch and the
// tilted axis (1, 1, 1) in 3D, left out in 2D. Known answers: +90 deg of roll takes y to z,
// +90 deg of pitch takes z to x, and 120 deg about (1, 1, 1) permutes the axes x -> y -> z.
TEST(ErrorSweep, TurnsAboutRollPitchAndATiltedAxis) {
  const coral::ToleranceConfig tol{0.3, 2.0};
  const std::vector<eval::TurnAxis> axes = {eval::TurnAxis::kRoll, eval::TurnAxis::kPitch,
                                            eval::TurnAxis::kTilted};
  const auto errors = eval::sweepErrors(tol, 3, {}, {90.0, 120.0, 180.0}, axes);
  ASSERT_EQ(errors.size(), 1u + 3u * (2u + 2u + 1u));
  std::map<std::string, Eigen::Isometry3d> by_label;
  for (const eval::SweepError& e : errors) {
    by_label[e.label] = e.delta;
    if (e.ground_truth) continue;
    EXPECT_NEAR(e.delta.translation().norm(), 0.0, 1e-12) << e.label;
    const double angle = Eigen::AngleAxisd(e.delta.linear()).angle() * 180.0 / M_PI;
    EXPECT_NEAR(angle, e.magnitude, 1e-9) << e.label;
  }
  ASSERT_EQ(by_label.count("roll+90deg") + by_label.count("pitch-90deg") +
                by_label.count("tilted+120deg") + by_label.count("tilted+180deg"),
            4u);
  EXPECT_EQ(by_label.count("tilted-180deg"), 0u) << "+180 = -180";
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(),
                        z = Eigen::Vector3d::UnitZ();
  EXPECT_TRUE((by_label["roll+90deg"] * y).isApprox(z, 1e-12));
  EXPECT_TRUE((by_label["pitch+90deg"] * z).isApprox(x, 1e-12));
  EXPECT_TRUE((by_label["tilted+120deg"] * x).isApprox(y, 1e-12));
  EXPECT_TRUE((by_label["tilted+120deg"] * y).isApprox(z, 1e-12));
  for (const eval::SweepError& e : errors)
    EXPECT_EQ(e.axis_name, e.label.rfind("tilted", 0) == 0 ? "tilted" : "") << e.label;
  // The yaw turns are the default grid's, whichever axes come with them.
  const auto yaw = eval::sweepErrors(tol, 3, {}, {90.0}, {eval::TurnAxis::kYaw});
  ASSERT_EQ(yaw.size(), 3u);
  EXPECT_EQ(yaw[1].label, "yaw+90deg");
  EXPECT_TRUE((yaw[1].delta * x).isApprox(y, 1e-12));
  // A 2D scan has no roll or pitch: only ground truth is left.
  EXPECT_EQ(eval::sweepErrors(tol, 2, {}, {90.0}, axes).size(), 1u);
  eval::TurnAxis a;
  EXPECT_TRUE(eval::parseTurnAxis("tilted", &a));
  EXPECT_EQ(a, eval::TurnAxis::kTilted);
  EXPECT_FALSE(eval::parseTurnAxis("Roll", &a));
}

// Errors between the axes (coral_error_sweep --oblique): per multiple k, directions between two
// translation axes at 22.5, 45 and 67.5 deg (x-y; in 3D also x-z, y-z) and x or y with yaw at
// shares (1, 1), (1, 0.5), (0.5, 1), all four sign pairs; each of size k by the verdict's own
// measure (coral::toleranceSize, the larger of |t| / tolerance and angle / rotation tolerance),
// and both of its components non-zero.
TEST(ErrorSweep, ObliqueErrorsLieBetweenTheAxesAtTheirMultiple) {
  const coral::ToleranceConfig tol{0.3, 2.0};
  for (int dim : {2, 3}) {
    const auto errors = eval::sweepErrors(tol, dim, {1, 4}, {}, {}, true);
    const std::size_t per_k = (dim == 2 ? 1 : 3) * 3 * 4 + 2 * 3 * 4;
    ASSERT_EQ(errors.size(), 1u + 2u * (dim == 2 ? 6u : 12u) + 2u * per_k) << dim;
    std::map<std::string, Eigen::Isometry3d> by_label;
    std::size_t oblique = 0;
    for (const eval::SweepError& e : errors) {
      by_label[e.label] = e.delta;
      if (e.axis_name != "oblique") continue;
      ++oblique;
      EXPECT_NEAR(coral::toleranceSize(e.delta, tol), e.multiple, 1e-9) << e.label;
      const Eigen::Vector3d t = e.delta.translation();
      const double yaw = std::abs(yawDeg(e.delta));
      const int nonzero = (std::abs(t.x()) > 1e-9) + (std::abs(t.y()) > 1e-9) +
                          (std::abs(t.z()) > 1e-9) + (yaw > 1e-9);
      EXPECT_EQ(nonzero, 2) << e.label;
      if (dim == 2) {
        EXPECT_NEAR(t.z(), 0.0, 1e-12) << e.label;
      }
    }
    EXPECT_EQ(oblique, 2 * per_k) << dim;
    // Known answers: a diagonal shares the length, a turn with a shift takes it whole.
    ASSERT_EQ(by_label.count("x+y-4"), 1u);
    EXPECT_TRUE(by_label["x+y-4"].translation().isApprox(
        Eigen::Vector3d(1.2 / std::sqrt(2.0), -1.2 / std::sqrt(2.0), 0.0), 1e-12));
    ASSERT_EQ(by_label.count("x-y+1@22.5"), 1u);
    EXPECT_TRUE(by_label["x-y+1@22.5"].translation().isApprox(
        Eigen::Vector3d(-0.3 * std::cos(M_PI / 8), 0.3 * std::sin(M_PI / 8), 0.0), 1e-12));
    ASSERT_EQ(by_label.count("y-yaw+1"), 1u);
    EXPECT_TRUE(by_label["y-yaw+1"].translation().isApprox(Eigen::Vector3d(0, -0.3, 0), 1e-12));
    EXPECT_NEAR(yawDeg(by_label["y-yaw+1"]), 2.0, 1e-9);
    ASSERT_EQ(by_label.count("x+yaw-4@1:0.5"), 1u);
    EXPECT_TRUE(
        by_label["x+yaw-4@1:0.5"].translation().isApprox(Eigen::Vector3d(1.2, 0, 0), 1e-12));
    EXPECT_NEAR(yawDeg(by_label["x+yaw-4@1:0.5"]), -4.0, 1e-9);
    EXPECT_EQ(by_label.count("x+z+1"), dim == 3 ? 1u : 0u);
  }
  // Off by default: the doc's tables are the axes' grid.
  for (const eval::SweepError& e : eval::sweepErrors(tol, 3)) EXPECT_NE(e.axis_name, "oblique");
}
