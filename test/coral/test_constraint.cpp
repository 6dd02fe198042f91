// The constraint term (coral/constraint.hpp) on point sets whose answer is known: a square
// room pins every direction by about one wall pair's points; a corridor without ends pins
// nothing along it (0); its end wall pins that direction by about that wall's points; a
// round room pins translation and leaves rotation about its centre free (0);
// nothing shared gives 0; the value does not depend on the frame. Then the gated verdict: a
// corridor slid 1.5 m along itself passes CorAl's relative check (Q is flat there) and is
// rejected by this term, which names itself. With a reference beam spacing the value does not
// depend on how densely the scanner samples the same room.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "coral_introspection/coral/constraint.hpp"
#include "coral_introspection/coral/verdict.hpp"

using namespace coral_introspection::coral;

namespace {

constexpr double kStep = 0.05;  // [m] point spacing along a wall

// Points every kStep from p to q (both ends included), z = 0.
void wall(double x0, double y0, double x1, double y1, Points* out) {
  const Vec3 p(x0, y0, 0.0), q(x1, y1, 0.0);
  const int n = static_cast<int>(std::lround((q - p).norm() / kStep));
  for (int i = 0; i <= n; ++i) out->push_back(p + (q - p) * (static_cast<double>(i) / n));
}

// radius 0.5 m as lidar_2d; 0.52: no neighbour exactly at the radius (a multiple of kStep),
// where rounding after a rigid motion would decide.
CoralConfig planar(double radius = 0.5) {
  CoralConfig c;
  c.dimension = 2;
  c.radius = radius;
  return c;
}

ToleranceConfig tolerance2d() { return ToleranceConfig::lidar2d(); }  // 0.3 m, 5 deg

Points transformed(const Points& pts, const Eigen::Isometry3d& T) {
  Points out;
  for (const Vec3& p : pts) out.push_back(T * p);
  return out;
}

const Eigen::Isometry3d kIdentity = Eigen::Isometry3d::Identity();  // b given in a's frame

}  // namespace

TEST(Constraint, SquareRoomIsPinnedByAWallPairInEveryDirection) {
  Points room;  // 10 m x 10 m: 201 points per wall
  wall(-5, -5, 5, -5, &room);
  wall(5, -5, 5, 5, &room);
  wall(5, 5, -5, 5, &room);
  wall(-5, 5, -5, -5, &room);
  const ConstraintResult r = registrationConstraint(room, room, kIdentity, planar(), tolerance2d());
  ASSERT_TRUE(r.valid);
  // Translation along x: the two walls of normal x, 2 x 201 points of weight 1, less the
  // corners (points within 0.5 m of a corner see both walls: weight < 1). Rotation about the
  // centre: 4 walls x sum of (along-wall offset)^2 x k^2, k = 5 deg / 0.3 m, about 570: more.
  EXPECT_GT(r.weakest, 0.9 * 402);
  EXPECT_LE(r.weakest, 402 + 1e-9);
  EXPECT_EQ(r.points, 2 * static_cast<int>(room.size()));
}

// A 10 m x 10 m square room as a 2D scanner at its centre sees it: one return every step_deg.
Points scannedRoom(double step_deg) {
  Points out;
  const int n = static_cast<int>(std::lround(360.0 / step_deg));
  for (int i = 0; i < n; ++i) {
    const double a = (i + 0.5) * step_deg * M_PI / 180.0;
    const double r = 5.0 / std::max(std::abs(std::cos(a)), std::abs(std::sin(a)));
    out.emplace_back(r * std::cos(a), r * std::sin(a), 0.0);
  }
  return out;
}

// The term counts points: the same room scanned at 0.5 deg gives about twice the value of 1
// deg. With the beam spacing of reference (GateConfig::constraint_beam_step_deg), both are in
// points at 1 deg: equal within a few per cent, and the 1 deg scan's value is unchanged.
// (The presets' worry is a denser scanner than the 1 deg logs their bounds were chosen on.)
TEST(Constraint, BeamSpacingShareMakesTheValueIndependentOfTheScannersDensity) {
  const Points fine = scannedRoom(0.5), coarse = scannedRoom(1.0), sparse = scannedRoom(2.0);
  EXPECT_DOUBLE_EQ(beamSpacingShare(coarse, 1.0), 1.0);  // the reference spacing: exactly 1
  EXPECT_NEAR(beamSpacingShare(fine, 1.0), 0.5, 1e-6);
  EXPECT_NEAR(beamSpacingShare(sparse, 1.0), 2.0, 1e-6);
  EXPECT_DOUBLE_EQ(beamSpacingShare(fine, 0.0), 1.0);  // off
  Points few(coarse.begin(), coarse.begin() + 8);
  EXPECT_DOUBLE_EQ(beamSpacingShare(few, 1.0), 1.0);  // too few bearings to tell
  auto weakest = [](const Points& s, double reference) {
    return registrationConstraint(s, s, kIdentity, planar(), tolerance2d(), reference).weakest;
  };
  const double raw_fine = weakest(fine, 0.0), raw_coarse = weakest(coarse, 0.0);
  ASSERT_GT(raw_coarse, 10.0);
  EXPECT_NEAR(raw_fine / raw_coarse, 2.0, 0.1);
  EXPECT_DOUBLE_EQ(weakest(coarse, 1.0), raw_coarse);
  EXPECT_NEAR(weakest(fine, 1.0) / raw_coarse, 1.0, 0.05);
  // A 2 deg scan counts each point twice, but loses points to CorAl's neighbour count (17-24
  // cm apart on these walls, within r = 0.5 m): it stays below, on the safe side of a bound.
  EXPECT_NEAR(weakest(sparse, 1.0), 2.0 * weakest(sparse, 0.0), 1e-9);
  EXPECT_LT(weakest(sparse, 1.0), raw_coarse);
}

TEST(Constraint, CorridorWithoutEndsPinsNothingAlongItAndItsEndWallDoes) {
  Points corridor;  // 2 m wide, 40 m long
  wall(-20, -1, 20, -1, &corridor);
  wall(-20, 1, 20, 1, &corridor);
  const ConstraintResult open =
      registrationConstraint(corridor, corridor, kIdentity, planar(), tolerance2d());
  EXPECT_LT(open.weakest, 1e-6);  // every normal is +-y: x is free
  Points closed = corridor;
  wall(20, -1, 20, 1, &closed);  // the end wall: 41 points of normal x
  const ConstraintResult end =
      registrationConstraint(closed, closed, kIdentity, planar(), tolerance2d());
  EXPECT_GT(end.weakest, 20.0);  // its points away from the corners pin x
  EXPECT_LE(end.weakest, 41.0 + 1e-9);
}

TEST(Constraint, RoundRoomLeavesRotationAboutItsCentreFree) {
  Points round;  // radius 4 m, a point every 0.05 m: every normal points at the centre
  const int n = static_cast<int>(2.0 * M_PI * 4.0 / kStep);
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * i / n;
    round.emplace_back(4.0 * std::cos(a), 4.0 * std::sin(a), 0.0);
  }
  // (p - c) x n = 0 for every point: turning about the centre moves nothing along a normal.
  // Without the rotation column the same room would look pinned: translation alone is held by
  // about half the points along any axis.
  const ConstraintResult r =
      registrationConstraint(round, round, kIdentity, planar(), tolerance2d());
  EXPECT_EQ(r.points, 2 * n);
  EXPECT_LT(r.weakest, 1e-6 * n);
}

TEST(Constraint, NothingSharedIsZeroAndTheFrameDoesNotMatter) {
  Points room;
  wall(0, 0, 4, 0, &room);
  wall(4, 0, 4, 3, &room);
  wall(4, 3, 0, 3, &room);
  const Points far = transformed(room, se2(50.0, 0.0, 0.0));
  const ConstraintResult none =
      registrationConstraint(room, far, kIdentity, planar(), tolerance2d());
  EXPECT_TRUE(none.valid);
  EXPECT_EQ(none.points, 0);
  EXPECT_EQ(none.weakest, 0.0);
  const ConstraintResult here =
      registrationConstraint(room, room, kIdentity, planar(0.52), tolerance2d());
  const Eigen::Isometry3d T = se2(3.0, -7.0, 0.6);
  const ConstraintResult moved = registrationConstraint(transformed(room, T), transformed(room, T),
                                                        kIdentity, planar(0.52), tolerance2d());
  EXPECT_GT(here.weakest, 1.0);
  EXPECT_NEAR(moved.weakest, here.weakest, 1e-6 * here.weakest);
}

TEST(Constraint, GatedVerdictRejectsACorridorSlidAlongItselfAndSaysWhy) {
  Scan a;  // a 60 m corridor seen from its middle; b is the same corridor from 1.5 m further
  wall(-30, -1, 30, -1, &a.points);
  wall(-30, 1, 30, 1, &a.points);
  Scan b;
  b.points = transformed(a.points, se2(-1.5, 0.0, 0.0));  // b's frame: 1.5 m along x
  // Judged at the identity: off by 1.5 m (5 tolerances) along the corridor.
  VerdictConfig cfg;
  cfg.method = VerdictMethod::kGated;
  cfg.tolerance = tolerance2d();
  cfg.gate.min_constraint = 0.3;
  const CoralConfig coral = planar();
  const AlignmentVerdict v = judgeAlignment(a, b, Eigen::Isometry3d::Identity(), coral, cfg);
  ASSERT_TRUE(v.valid);
  EXPECT_FALSE(v.relative.misaligned);  // Q is flat along the corridor: CorAl cannot tell
  EXPECT_FALSE(v.aligned);
  EXPECT_NE(v.rejected_by.find("gate: constraint"), std::string::npos) << v.rejected_by;
  EXPECT_LT(v.constraint.weakest, 0.3);
  cfg.gate.min_constraint = 0.0;  // without the term the slid corridor is "aligned"
  const AlignmentVerdict off = judgeAlignment(a, b, Eigen::Isometry3d::Identity(), coral, cfg);
  EXPECT_TRUE(off.valid && off.aligned);
  EXPECT_FALSE(off.constraint.valid);  // not measured when its gate is off
}
