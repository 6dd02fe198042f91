// eval::sweepErrors: the errors coral_error_sweep and test_preset_verdicts judge.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

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
