// A planar scan's beam spacing and the thinning of a finer scan to the spacing a preset's bounds
// were chosen at (coral/beam_spacing.hpp, CoralConfig::beam_step_deg): known fans of beams, the
// kept beams by their bearing whatever returned, and CorAl on a 0.5 deg pair thinned to 1 deg
// equal to CorAl on the 1 deg pair.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "coral_introspection/coral/beam_spacing.hpp"
#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/coral/coral_pair.hpp"

using namespace coral_introspection::coral;

namespace {

constexpr double kDeg = M_PI / 180.0;

// A fan of `count` beams from start_deg in steps of step_deg about `origin`, each hitting a
// 6 x 4 m room around the origin (a wall at x = 4 m, y = +-2 m, x = -2 m); beams listed in
// `gaps` returned nothing.
Points fan(int count, double start_deg, double step_deg, const Vec3& origin = Vec3::Zero(),
           const std::vector<int>& gaps = {}) {
  Points out;
  for (int j = 0; j < count; ++j) {
    if (std::find(gaps.begin(), gaps.end(), j) != gaps.end()) continue;
    const double a = (start_deg + j * step_deg) * kDeg, c = std::cos(a), s = std::sin(a);
    double r = std::numeric_limits<double>::infinity();
    if (c > 1e-9) r = std::min(r, 4.0 / c);
    if (c < -1e-9) r = std::min(r, 2.0 / -c);
    if (std::abs(s) > 1e-9) r = std::min(r, 2.0 / std::abs(s));
    out.push_back(origin + Vec3(r * c, r * s, 0.0));
  }
  return out;
}

// Bearings [deg] about origin, rounded to 1e-6.
std::vector<double> bearings(const Points& pts, const Vec3& origin = Vec3::Zero()) {
  std::vector<double> out;
  for (const Vec3& p : pts)
    out.push_back(std::round(std::atan2(p.y() - origin.y(), p.x() - origin.x()) / kDeg * 1e6) /
                  1e6);
  return out;
}

}  // namespace

TEST(BeamSpacing, MedianStepOfAFanWithGaps) {
  EXPECT_NEAR(medianBeamStepDeg(fan(361, -90.0, 0.5), Vec3::Zero()), 0.5, 1e-9);
  EXPECT_NEAR(medianBeamStepDeg(fan(180, -90.0, 1.0, Vec3::Zero(), {3, 4, 5, 40}), Vec3::Zero()),
              1.0, 1e-9);
  const Vec3 o(3.0, -4.0, 0.0);  // about the scan's own origin, not the frame's
  EXPECT_NEAR(medianBeamStepDeg(fan(91, -90.0, 2.0, o), o), 2.0, 1e-9);
  EXPECT_TRUE(std::isnan(medianBeamStepDeg(fan(10, 0.0, 1.0), Vec3::Zero())));  // 9 steps
  // The same fan seen from 20 m away (a scan not in its sensor frame): irregular steps, no
  // spacing, and nothing thinned.
  const Points far = fan(361, -90.0, 0.5, Vec3(20.0, 5.0, 0.0));
  EXPECT_TRUE(std::isnan(medianBeamStepDeg(far, Vec3::Zero())));
  Points storage;
  std::size_t dropped = 0;
  EXPECT_EQ(&thinToBeamStep(far, Vec3::Zero(), 1.0, &storage, &dropped), &far);
}

TEST(BeamSpacing, AFinerScanKeepsTheBeamsOfTheReferenceGridWhateverReturned) {
  Points storage;
  std::size_t dropped = 0;
  // 0.5 deg from -90: the beams at whole degrees stay, also when beam 0 (-90 deg) and others
  // returned nothing (the grid's phase comes from every bearing, not from the first one).
  const Points fine = fan(361, -90.0, 0.5, Vec3::Zero(), {0, 7, 100, 101});
  const Points& thin = thinToBeamStep(fine, Vec3::Zero(), 1.0, &storage, &dropped);
  EXPECT_EQ(bearings(thin), bearings(fan(181, -90.0, 1.0, Vec3::Zero(), {0, 50})));
  EXPECT_EQ(dropped, fine.size() - thin.size());
  // CARMEN's 360-beam mode lies half a step off whole numbers of steps: still every second.
  dropped = 0;
  const Points sick360 = fan(360, -89.75, 0.5);
  EXPECT_EQ(thinToBeamStep(sick360, Vec3::Zero(), 1.0, &storage, &dropped).size(), 180u);
  EXPECT_EQ(dropped, 180u);
  // 0.25 deg over 100 deg: every fourth, about the scan's own origin.
  const Vec3 o(-2.0, 1.0, 0.0);
  dropped = 0;
  const Points quarter = fan(401, -50.0, 0.25, o);
  EXPECT_EQ(bearings(thinToBeamStep(quarter, o, 1.0, &storage, &dropped), o),
            bearings(fan(101, -50.0, 1.0, o), o));
  // The reference spacing, a coarser one, 0.75 deg (k = 1) and off: the input itself.
  dropped = 0;
  const std::vector<Points> kept = {fan(180, -90.0, 1.0), fan(91, -90.0, 2.0),
                                    fan(240, -90.0, 0.75)};
  for (const Points& p : kept)
    EXPECT_EQ(&thinToBeamStep(p, Vec3::Zero(), 1.0, &storage, &dropped), &p);
  EXPECT_EQ(&thinToBeamStep(fine, Vec3::Zero(), 0.0, &storage, &dropped), &fine);
  EXPECT_EQ(dropped, 0u);
}

TEST(BeamSpacing, ShareIsOneAtTheReferenceSpacing) {
  EXPECT_DOUBLE_EQ(beamSpacingShare(fan(180, -90.0, 1.0), 1.0), 1.0);
  EXPECT_NEAR(beamSpacingShare(fan(361, -90.0, 0.5), 1.0), 0.5, 1e-9);
  EXPECT_DOUBLE_EQ(beamSpacingShare(fan(361, -90.0, 0.5), 0.0), 1.0);
}

// The point of the setting: a 0.5 deg scanner's pair, thinned, is judged on exactly the points
// a 1 deg scanner gives, so the bounds chosen at 1 deg hold. (On this clean room the entropies
// barely depend on the density; on real scans they do: doc/loop_closure.md.)
TEST(BeamSpacing, CoralOfAFinerPairThinnedEqualsCoralOfTheReferencePair) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.01);
  auto noisy = [&](Points p) {
    for (Vec3& q : p) q.head<2>() *= 1.0 + noise(rng) / q.head<2>().norm();
    return p;
  };
  Scan a_fine, b_fine;
  a_fine.points = noisy(fan(361, -90.0, 0.5));
  b_fine.points = noisy(fan(361, -90.0, 0.5));
  Scan a_coarse = a_fine, b_coarse = b_fine;  // the same readings at whole degrees
  for (Scan* s : {&a_coarse, &b_coarse}) {
    Points even;
    for (std::size_t j = 0; j < s->points.size(); j += 2) even.push_back(s->points[j]);
    s->points = even;
  }
  CoralConfig cfg;
  cfg.dimension = 2;
  cfg.radius = 0.5;
  cfg.epsilon = 1e-4;
  const Eigen::Isometry3d T = se2(0.05, -0.02, 0.01);
  const CoralResult coarse = CoralPair(a_coarse, b_coarse, cfg).evaluate(T);
  ASSERT_TRUE(coarse.valid) << coarse.reason;
  const CoralResult fine_raw = CoralPair(a_fine, b_fine, cfg).evaluate(T);
  cfg.beam_step_deg = 1.0;
  const CoralPair thinned(a_fine, b_fine, cfg);
  const CoralResult fine = thinned.evaluate(T);
  EXPECT_EQ(fine.num_beam_thinned, 360u);  // 180 of each scan's 361
  EXPECT_EQ(thinned.points(1).size(), b_coarse.points.size());
  EXPECT_NEAR(fine.h_joint, coarse.h_joint, 1e-9);
  EXPECT_NEAR(fine.h_sep, coarse.h_sep, 1e-9);
  EXPECT_NEAR(fine.quality, coarse.quality, 1e-9);
  EXPECT_EQ(fine_raw.num_points_b, 361u);  // off: every reading scored
  cfg.beam_step_deg = -1.0;
  EXPECT_NE(cfg.validate().find("beam_step_deg"), std::string::npos);
}
