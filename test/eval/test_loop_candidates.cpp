// Registration of loop candidates (eval/loop_candidates.hpp): the 2D registrations on the
// planar synthetic yard pair and the 3D point-to-point ICP (LIO-SAM's settings) on its
// 16-ring version, whose relative poses are known, and the registration names each dimension
// accepts.
#include <gtest/gtest.h>

#include <limits>
#include <map>
#include <string>
#include <vector>

#include "coral_introspection/eval/loop_candidates.hpp"
#include "support/yard_pair.hpp"

namespace coral_introspection {
namespace {

// The yard pair (planar in 2D, 16 rings in 3D) registered by `registration` from its true pose
// moved by start_offset.
eval::LoopCandidate registerYard(int dimension, const std::string& registration,
                                 const Eigen::Isometry3d& start_offset, Eigen::Isometry3d* T_true) {
  const test::YardPair p = test::yardPair(dimension == 3 ? 16 : 1);
  eval::LoopCandidateConfig cfg = eval::evaluationCandidates(dimension, coral::ToleranceConfig());
  cfg.registration = registration;
  EXPECT_EQ(cfg.validate(), "");
  eval::LoopCandidate c;
  eval::registerPair(p.a.points, p.b.points, p.T_a_b * start_offset, cfg, &c);
  *T_true = p.T_a_b;
  return c;
}

TEST(LoopCandidates, PointToLineRegistrationReachesTheKnownPose) {
  // From a back end's guess 0.5 m and 10 deg off (the evaluation's offset), as the CARMEN
  // revisits are registered again.
  for (const Eigen::Isometry3d& d :
       {coral::se2(0.5, 0.0, 10.0 * M_PI / 180.0), coral::se2(0.0, -0.5, -10.0 * M_PI / 180.0)}) {
    Eigen::Isometry3d T_true;
    const eval::LoopCandidate c = registerYard(2, "point_to_line", d, &T_true);
    ASSERT_TRUE(c.converged);
    double t = 0, r = 0;
    eval::relativeError(c.T_a_b, T_true, &t, &r);
    EXPECT_LT(t, 0.05);  // [m] a sixth of the 0.3 m tolerance
    EXPECT_LT(r, 0.5);   // [deg]
  }
}

// Every registration of both dimensions on a scan with too few points (an empty keyframe, a
// blinded sensor) is not run: PCL dereferences an empty cloud's search tree. The candidate
// keeps its initial pose, not converged, so every gate rejects it; a scan of exactly the
// minimum is registered.
TEST(LoopCandidates, AScanWithTooFewPointsIsNotRegistered) {
  const test::YardPair p = test::yardPair(16);
  const Eigen::Isometry3d init = p.T_a_b * coral::se2(0.2, 0.1, 0.05);
  const coral::Points few(p.b.points.begin(),
                          p.b.points.begin() + (eval::kMinRegistrationPoints - 1));
  for (int dimension : {2, 3})
    for (const std::string registration : dimension == 3
                                              ? std::vector<std::string>{"gicp", "ndt", "icp"}
                                              : std::vector<std::string>{"icp", "point_to_line"})
      for (const coral::Points& b : {coral::Points(), few}) {
        eval::LoopCandidateConfig cfg = eval::evaluationCandidates(dimension, {});
        cfg.registration = registration;
        eval::LoopCandidate c;
        eval::registerPair(p.a.points, b, init, cfg, &c);
        EXPECT_FALSE(c.converged) << registration << " " << b.size();
        EXPECT_TRUE(c.T_a_b.isApprox(init)) << registration;
        EXPECT_EQ(c.fitness, std::numeric_limits<double>::max());
        eval::registerPair(b, p.b.points, init, cfg, &c);  // as the target
        EXPECT_FALSE(c.converged) << registration << " " << b.size();
      }
  eval::LoopCandidate c;
  const coral::Points enough(p.b.points.begin(), p.b.points.begin() + eval::kMinRegistrationPoints);
  eval::registerPair(p.a.points, enough, init, eval::evaluationCandidates(3, {}), &c);
  EXPECT_LT(c.fitness, std::numeric_limits<double>::max());
}

// The CSVs write a scan that was not registered as "inf", not as 1.79769e+308.
TEST(LoopCandidates, FitnessCellWritesNoCorrespondenceAsInf) {
  EXPECT_EQ(eval::fitnessCell(std::numeric_limits<double>::max()), "inf");
  EXPECT_EQ(eval::fitnessCell(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(eval::fitnessCell(std::nan("")), "inf");
  EXPECT_EQ(eval::fitnessCell(0.0314159), "0.0314159");
  EXPECT_EQ(eval::fitnessCell(0.0), "0");
}

TEST(LoopCandidates, PointToLineStaysPlanar) {
  Eigen::Isometry3d T_true;
  const eval::LoopCandidate c =
      registerYard(2, "point_to_line", coral::se2(0.3, 0.2, 0.1), &T_true);
  EXPECT_NEAR(c.T_a_b.translation().z(), 0.0, 1e-6);
  EXPECT_NEAR(std::abs(c.T_a_b.linear()(2, 2)), 1.0, 1e-6);  // rotation about z only
}

// Point-to-point ICP on ring scans stops short: the nearest point of a ring lies on the same
// ring of the other scan, which pulls towards the start (measured: from 0.27 m / 3 deg off
// it ends 0.19 m off; GICP, whose plane-to-plane terms slide along the rings, within 5 cm).
// That is LIO-SAM's registration scan to scan, and why a gate has to judge where it stops.
TEST(LoopCandidates, PointToPointIcpIn3dMovesTowardsTheKnownPose) {
  Eigen::Isometry3d start = coral::se2(0.2, -0.15, 3.0 * M_PI / 180.0);
  start.translation().z() = 0.1;
  double t0 = 0, r0 = 0;
  eval::relativeError(start, Eigen::Isometry3d::Identity(), &t0, &r0);
  std::map<std::string, std::pair<double, double>> error;  // registration -> (t [m], r [deg])
  for (const char* registration : {"icp", "gicp"}) {
    Eigen::Isometry3d T_true;
    const eval::LoopCandidate c = registerYard(3, registration, start, &T_true);
    ASSERT_TRUE(c.converged) << registration;
    eval::relativeError(c.T_a_b, T_true, &error[registration].first, &error[registration].second);
  }
  EXPECT_LT(error["icp"].first, 0.8 * t0);
  EXPECT_LT(error["icp"].second, 0.5 * r0);
  EXPECT_LT(error["gicp"].first, 0.05);  // [m] a sixth of the 0.3 m tolerance
  EXPECT_LT(error["gicp"].second, 0.5);  // [deg]
  EXPECT_GT(error["icp"].first, error["gicp"].first);
}

TEST(LoopCandidates, EachDimensionNamesItsRegistrations) {
  const coral::ToleranceConfig tol;
  EXPECT_EQ(eval::evaluationCandidates(2, tol).registration, "icp");
  EXPECT_EQ(eval::evaluationCandidates(3, tol).registration, "gicp");
  for (const char* ok : {"icp", "point_to_line"}) {
    eval::LoopCandidateConfig c = eval::evaluationCandidates(2, tol);
    c.registration = ok;
    EXPECT_EQ(c.validate(), "") << ok;
  }
  for (const char* bad : {"gicp", "ndt", "point-to-line", ""}) {
    eval::LoopCandidateConfig c = eval::evaluationCandidates(2, tol);
    c.registration = bad;
    EXPECT_NE(c.validate().find("icp or point_to_line for 2D"), std::string::npos) << bad;
  }
  for (const char* ok : {"gicp", "ndt", "icp"}) {
    eval::LoopCandidateConfig c = eval::evaluationCandidates(3, tol);
    c.registration = ok;
    EXPECT_EQ(c.validate(), "") << ok;
  }
  eval::LoopCandidateConfig c3 = eval::evaluationCandidates(3, tol);
  c3.registration = "point_to_line";
  EXPECT_NE(c3.validate().find("gicp, ndt or icp for 3D"), std::string::npos);
}

}  // namespace
}  // namespace coral_introspection
