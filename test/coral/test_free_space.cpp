// The free-space check (coral/free_space.hpp) on ray-cast scenes whose answer is known: no
// conflict at the true relative pose; a corridor slid along its axis (where CorAl's Q is flat
// and the relative check passes) and a shifted room put the end walls of one scan into the
// other's free space; the margin boundary to the centimetre; unseen directions untested. Then
// the gated verdict naming the term when it rejects.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "coral_introspection/coral/free_space.hpp"
#include "coral_introspection/coral/verdict.hpp"

using namespace coral_introspection::coral;

namespace {

struct Segment {
  Eigen::Vector2d p, q;
};

// A closed axis-aligned rectangle [x0, x1] x [y0, y1] as four walls.
std::vector<Segment> box(double x0, double y0, double x1, double y1) {
  const Eigen::Vector2d a(x0, y0), b(x1, y0), c(x1, y1), d(x0, y1);
  return {{a, b}, {b, c}, {c, d}, {d, a}};
}

// A 360-degree planar scan with one beam per step_deg from `pose` (world x, y, yaw), points in
// the sensor frame (z = 0), 5 mm range noise from a fixed seed.
Scan scan2d(const std::vector<Segment>& walls, double x, double y, double yaw, unsigned seed,
            double step_deg = 1.0) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.005);
  Scan s;
  const Eigen::Vector2d o(x, y);
  for (int i = 0; i < static_cast<int>(std::lround(360.0 / step_deg)); ++i) {
    const double a = (i + 0.5) * step_deg * M_PI / 180.0;
    const Eigen::Vector2d d(std::cos(yaw + a), std::sin(yaw + a));
    double best = std::numeric_limits<double>::infinity();
    for (const Segment& w : walls) {  // ray o + t d against segment p + u (q - p)
      const Eigen::Vector2d e = w.q - w.p;
      const double den = d.x() * e.y() - d.y() * e.x();
      if (std::abs(den) < 1e-12) continue;
      const Eigen::Vector2d r = w.p - o;
      const double t = (r.x() * e.y() - r.y() * e.x()) / den;
      const double u = (r.x() * d.y() - r.y() * d.x()) / den;
      if (t > 0.0 && u >= 0.0 && u <= 1.0) best = std::min(best, t);
    }
    if (std::isfinite(best)) {
      const double r = best + noise(rng);
      s.points.emplace_back(r * std::cos(a), r * std::sin(a), 0.0);
    }
  }
  return s;
}

// A's pose inverse times B's: maps B's sensor frame into A's.
Eigen::Isometry3d relative(double xa, double ya, double yawa, double xb, double yb, double yawb) {
  return se2(xa, ya, yawa).inverse() * se2(xb, yb, yawb);
}

FreeSpaceResult conflict2d(const Scan& a, const Scan& b, const Eigen::Isometry3d& T) {
  return freeSpaceConflict(a.points, a.origin, b.points, b.origin, T, 2, FreeSpaceConfig());
}

// A corridor 2 m wide and 12 m long, closed at both ends; scans 3 m apart along it.
const std::vector<Segment> kCorridor = box(0.0, 0.0, 12.0, 2.0);

}  // namespace

TEST(FreeSpace, TruePoseOfARoomHasNoConflict) {
  std::vector<Segment> room = box(0.0, 0.0, 10.0, 6.0);
  room.push_back({{5.0, 0.0}, {5.0, 3.5}});  // an inner wall: occlusions both ways
  const Scan a = scan2d(room, 2.0, 3.0, 0.0, 1), b = scan2d(room, 7.5, 2.0, 0.6, 2);
  const FreeSpaceResult r = conflict2d(a, b, relative(2.0, 3.0, 0.0, 7.5, 2.0, 0.6));
  ASSERT_TRUE(r.valid);
  EXPECT_GT(r.tested, 200);  // most points of each scan lie where the other saw
  EXPECT_EQ(r.conflicts, 0);
  EXPECT_EQ(r.conflict, 0.0);
}

// A person (a 0.4 m square) stands in the room when b is taken, where a saw through to the
// far wall: at the true pose its points are in a's free space, a small group that
// min_extent (1 m) leaves out; counted with min_extent 0.
TEST(FreeSpace, APersonWhoMovedIsNotAConflict) {
  std::vector<Segment> room = box(0.0, 0.0, 10.0, 6.0);
  const Scan a = scan2d(room, 2.0, 3.0, 0.0, 1);
  for (const Segment& s : box(5.0, 2.8, 5.4, 3.2)) room.push_back(s);
  const Scan b = scan2d(room, 7.5, 2.0, 0.6, 2);
  const Eigen::Isometry3d truth = relative(2.0, 3.0, 0.0, 7.5, 2.0, 0.6);
  const FreeSpaceResult r = conflict2d(a, b, truth);
  ASSERT_TRUE(r.valid);
  EXPECT_EQ(r.conflicts, 0);
  FreeSpaceConfig every;
  every.min_extent = 0.0;
  const FreeSpaceResult all =
      freeSpaceConflict(a.points, a.origin, b.points, b.origin, truth, 2, every);
  EXPECT_GE(all.conflicts, 5);  // the person's side facing b: ~0.4 m at 2.5 m, 9 beams
}

TEST(FreeSpace, CorridorSlidAlongItsAxisPutsEndWallsIntoFreeSpace) {
  const Scan a = scan2d(kCorridor, 4.0, 1.0, 0.0, 3), b = scan2d(kCorridor, 7.0, 1.0, 0.0, 4);
  const Eigen::Isometry3d truth = relative(4.0, 1.0, 0.0, 7.0, 1.0, 0.0);
  const FreeSpaceResult ok = conflict2d(a, b, truth);
  ASSERT_TRUE(ok.valid);
  EXPECT_EQ(ok.conflicts, 0);
  // Slid by 1.5 m: the side walls still coincide, but b's far end wall (5 m ahead of b) lands
  // 1.5 m in front of a's (8 m ahead of a), and a's back wall 1.5 m in front of b's.
  const FreeSpaceResult slid = conflict2d(a, b, truth * se2(-1.5, 0.0, 0.0));
  ASSERT_TRUE(slid.valid);
  // The end walls subtend 2 atan(1 / d) at distance d: >= 12 beams each way at 8 m and 7 m.
  EXPECT_GE(slid.conflicts, 20);
  EXPECT_GT(slid.conflict, 0.05);
  // Slid by less than the margin (0.5 m): nothing conflicts.
  EXPECT_EQ(conflict2d(a, b, truth * se2(-0.3, 0.0, 0.0)).conflicts, 0);
}

// A scanner coarser than the 1 deg bins left every other bin empty, and a point next to an empty
// bin is untested: the term had no result at 2 deg (every ACES candidate resampled to 2 deg).
// Its bins are now 1.1 of its beam steps wide. Coarser beams see less: the slid corridor's end
// walls are found at 2 deg, with fewer points than at 1 deg (FreeSpace.CorridorSlid...).
TEST(FreeSpace, ACoarserScannerIsTestedInBinsOfItsSpacing) {
  for (const double step : {2.0, 3.0}) {
    const Scan a = scan2d(kCorridor, 4.0, 1.0, 0.0, 3, step),
               b = scan2d(kCorridor, 7.0, 1.0, 0.0, 4, step);
    const Eigen::Isometry3d truth = relative(4.0, 1.0, 0.0, 7.0, 1.0, 0.0);
    const FreeSpaceResult ok = conflict2d(a, b, truth);
    ASSERT_TRUE(ok.valid) << step << " deg: " << ok.tested << " tested";
    EXPECT_GT(ok.tested, static_cast<int>(a.points.size()));  // most of both scans
    EXPECT_EQ(ok.conflicts, 0);
    const FreeSpaceResult slid = conflict2d(a, b, truth * se2(-1.5, 0.0, 0.0));
    ASSERT_TRUE(slid.valid);
    if (step == 2.0) {
      EXPECT_GE(slid.conflicts, 8);
      EXPECT_GT(slid.conflict, 0.04);
    }
  }
}

TEST(FreeSpace, SwappingTheScansGivesTheSameConflict) {
  const Scan a = scan2d(kCorridor, 4.0, 1.0, 0.0, 3), b = scan2d(kCorridor, 7.0, 1.0, 0.2, 4);
  const Eigen::Isometry3d T = relative(4.0, 1.0, 0.0, 7.0, 1.0, 0.2) * se2(-1.2, 0.1, 0.05);
  const FreeSpaceResult ab = conflict2d(a, b, T), ba = conflict2d(b, a, T.inverse());
  EXPECT_EQ(ab.tested, ba.tested);
  EXPECT_EQ(ab.conflicts, ba.conflicts);
  EXPECT_DOUBLE_EQ(ab.conflict, ba.conflict);
}

TEST(FreeSpace, ConflictStartsExactlyAtTheMargin) {
  // a sees a wall 5 m ahead over +-10 deg; b holds one point straight ahead.
  Points wall;
  for (int i = -10; i <= 10; ++i) {
    const double ang = (i + 0.5) * M_PI / 180.0;
    wall.emplace_back(5.0 * std::cos(ang), 5.0 * std::sin(ang), 0.0);
  }
  FreeSpaceConfig cfg;
  cfg.min_tested = 1;
  cfg.min_extent = 0.0;  // a single point: every conflict counts
  const double ahead = 0.2 * M_PI / 180.0;
  auto at = [&](double r) {
    const Points b = {Vec3(r * std::cos(ahead), r * std::sin(ahead), 0.0)};
    return freeSpaceConflict(wall, Vec3::Zero(), b, Vec3::Zero(), Eigen::Isometry3d::Identity(), 2,
                             cfg);
  };
  // The nearest return of the bin and its neighbours is at 5 m (every point lies on r = 5).
  EXPECT_EQ(at(5.0 - cfg.margin - 0.01).conflicts, 1);
  EXPECT_EQ(at(5.0 - cfg.margin + 0.01).conflicts, 0);
  EXPECT_EQ(at(4.0).conflict, 1.0);  // 1 of 1 tested (b's bins hold no neighbours for a's points)
  EXPECT_EQ(at(7.0).conflicts, 0);   // behind the wall: occluded, not free
  // A direction a never saw (90 deg) is not tested; too few tested: no result.
  const Points side = {Vec3(0.0, 2.0, 0.0)};
  const FreeSpaceResult unseen = freeSpaceConflict(wall, Vec3::Zero(), side, Vec3::Zero(),
                                                   Eigen::Isometry3d::Identity(), 2, cfg);
  EXPECT_EQ(unseen.tested, 0);
  EXPECT_FALSE(unseen.valid);
}

TEST(FreeSpace, ShiftedRoomIn3dConflicts) {
  // A lidar 1 m above the floor of an 8 x 6 x 3 m box: rays every 0.5 deg in azimuth, every
  // 1 deg in elevation from -30 to +30 deg, cast against the six faces.
  auto scan3d = [](const Vec3& o) {
    Scan s;
    const Vec3 lo(0, 0, 0), hi(8, 6, 3);
    for (int e = -30; e <= 30; ++e)
      for (int k = 0; k < 720; ++k) {
        const double az = (k + 0.5) * M_PI / 360.0, el = (e + 0.25) * M_PI / 180.0;
        const Vec3 d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
        double t = std::numeric_limits<double>::infinity();
        for (int i = 0; i < 3; ++i)  // exit distance of the box along each axis
          if (std::abs(d[i]) > 1e-12) t = std::min(t, ((d[i] > 0 ? hi[i] : lo[i]) - o[i]) / d[i]);
        s.points.push_back(t * d);
      }
    return s;
  };
  const Scan a = scan3d(Vec3(3, 3, 1)), b = scan3d(Vec3(5, 2.5, 1));
  Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();
  truth.translation() = Vec3(2, -0.5, 0);
  FreeSpaceConfig cfg;
  const FreeSpaceResult ok =
      freeSpaceConflict(a.points, a.origin, b.points, b.origin, truth, 3, cfg);
  ASSERT_TRUE(ok.valid);
  EXPECT_EQ(ok.conflicts, 0);
  Eigen::Isometry3d off = truth;
  off.translation().x() += 1.5;  // b's wall at x = 0 now 1.5 m in front of a's (and back)
  const FreeSpaceResult bad =
      freeSpaceConflict(a.points, a.origin, b.points, b.origin, off, 3, cfg);
  ASSERT_TRUE(bad.valid);
  // That wall holds ~6 % of b's rays (floor and ceiling slide along themselves: no conflict).
  EXPECT_GT(bad.conflicts, 1000);
  EXPECT_GT(bad.conflict, 0.04);
  cfg.min_extent = 7.0;  // wider than the 6 m wall: no group counts
  EXPECT_EQ(freeSpaceConflict(a.points, a.origin, b.points, b.origin, off, 3, cfg).conflicts, 0);
}

TEST(FreeSpace, ConfigValidation) {
  FreeSpaceConfig c;
  EXPECT_EQ(c.validate(), "");
  c.bin_deg = 0.0;
  EXPECT_NE(c.validate().find("bin_deg"), std::string::npos);
  c = FreeSpaceConfig();
  c.margin = -0.1;
  EXPECT_NE(c.validate().find("margin"), std::string::npos);
  GateConfig g;
  g.max_free_space = 1.5;
  EXPECT_NE(g.validate().find("max_free_space"), std::string::npos);
}

// The corridor slid by 1.5 m: Q is flat along the corridor, so the relative check accepts
// it; the gate's free-space term rejects it and says so. At the true pose it passes.
TEST(FreeSpace, GatedVerdictRejectsTheSlidCorridorAndNamesTheTerm) {
  const Scan a = scan2d(kCorridor, 4.0, 1.0, 0.0, 3), b = scan2d(kCorridor, 7.0, 1.0, 0.0, 4);
  const Eigen::Isometry3d truth = relative(4.0, 1.0, 0.0, 7.0, 1.0, 0.0);
  CoralConfig coral;
  coral.dimension = 2;
  coral.radius = 0.5;
  coral.epsilon = 1e-4;
  VerdictConfig v;
  v.method = VerdictMethod::kGated;
  v.tolerance = ToleranceConfig::lidar2d();
  v.gate.max_free_space = 0.02;
  const Eigen::Isometry3d slid = truth * se2(-1.5, 0.0, 0.0);
  const AlignmentVerdict at_truth = judgeAlignment(a, b, truth, coral, v);
  ASSERT_TRUE(at_truth.valid) << at_truth.reason;
  EXPECT_TRUE(at_truth.aligned) << at_truth.rejected_by;
  EXPECT_TRUE(at_truth.free_space.valid);
  const AlignmentVerdict at_slid = judgeAlignment(a, b, slid, coral, v);
  ASSERT_TRUE(at_slid.valid) << at_slid.reason;
  EXPECT_FALSE(at_slid.relative.misaligned);  // what CorAl alone says: the corridor is flat
  EXPECT_FALSE(at_slid.aligned);
  EXPECT_NE(at_slid.rejected_by.find("free-space conflict"), std::string::npos)
      << at_slid.rejected_by;
  // With the term off (the default) the slid corridor passes: the term is what rejects it.
  v.gate.max_free_space = 1.0;
  const AlignmentVerdict off = judgeAlignment(a, b, slid, coral, v);
  EXPECT_TRUE(off.aligned);
  EXPECT_FALSE(off.free_space.valid);  // not measured when the gate does not use it
}
