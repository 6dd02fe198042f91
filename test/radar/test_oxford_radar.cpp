// Radar front end on real Oxford Radar RobotCar scans (skipped without ../shared/data):
// feature counts, GT consistency of the RIP features, and CorAl Q ordering at radar settings.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/coral/neighbour_grid.hpp"
#include "coral_introspection/eval/oxford_dataset.hpp"
#include "coral_introspection/radar/deskew.hpp"
#include "coral_introspection/radar/polar_scan.hpp"
#include "coral_introspection/radar/rip_features.hpp"
#include "support/test_data.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::radar;
using namespace coral_introspection::eval;

namespace {
// RIP features of every scan, optionally de-skewed by the online policy
// (radar::deskewVelocities) on the ground-truth poses.
std::vector<RadarFeatures> extractAll(const OxfordDataset& ds, bool compensate) {
  const std::size_t n = ds.png_paths.size();
  std::vector<RadarFeatures> out(n);
  std::vector<double> stamps(n);
  Isometries poses;
  for (std::size_t i = 0; i < n; ++i) {
    PolarScan scan;
    std::string err;
    EXPECT_TRUE(loadOxfordScan(ds.png_paths[i], &scan, &err)) << err;
    EXPECT_TRUE(extractRipFeatures(scan, RipConfig(), &out[i], &err)) << err;
    stamps[i] = scan.stamp;
    poses.push_back(ds.T_first_scan(i));
  }
  if (!compensate) return out;
  const auto velocities = deskewVelocities(stamps, poses);
  for (std::size_t i = 0; i < n; ++i)
    if (velocities[i]) compensateMotion(*velocities[i], stamps[i], &out[i]);
  return out;
}

// Fraction of b's features (mapped by T_a_b) with a partner in a within radius.
double matchFraction(const Points& a, const Points& b, const Eigen::Isometry3d& T_a_b,
                     double radius) {
  NeighbourGrid grid(a, radius, 2);
  std::size_t hit = 0;
  for (const Vec3& p : b) {
    bool found = false;
    grid.forEachWithin(T_a_b * p, radius, [&](const Vec3&, std::size_t) { found = true; });
    hit += found ? 1 : 0;
  }
  return b.empty() ? 0.0 : static_cast<double>(hit) / b.size();
}

CoralConfig radarCoral() { return CoralConfig::radarPaper(); }  // Sec. V-A
}  // namespace

TEST(OxfordRadar, DatasetLoadsWithGroundTruth) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  OxfordDataset ds;
  std::string err;
  ASSERT_TRUE(ds.load(coral_data, &err)) << err;
  ASSERT_EQ(ds.stamps_us.size(), 11u);
  ASSERT_EQ(ds.T_prev_curr.size(), 11u);
  EXPECT_TRUE(ds.T_prev_curr[0].isApprox(Eigen::Isometry3d::Identity()));
  for (std::size_t i = 1; i < 11; ++i) {
    // The car drives forward at a few m/s: 0.25 s apart, well under 10 m between scans.
    EXPECT_LT(ds.T_prev_curr[i].translation().norm(), 10.0);
  }
  const Eigen::Isometry3d T = ds.T_first_scan(3);
  EXPECT_TRUE(T.isApprox(ds.T_prev_curr[1] * ds.T_prev_curr[2] * ds.T_prev_curr[3]));
  EXPECT_FALSE(ds.load(coral_data + "/nonexistent", &err));
}

TEST(OxfordRadar, AMalformedGroundTruthNumberIsRefused) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  // The same scans with the first ground-truth row's x written otherwise: std::stod read "0.5x"
  // as 0.5 and "nan" as a pose; the reader refuses both and names the row.
  namespace fs = std::filesystem;
  const fs::path dir = coral_test::tempPath("oxford_malformed", "");
  fs::create_directories(dir / "gt");
  fs::create_directory_symlink(fs::absolute(coral_data + "/radar"), dir / "radar");
  fs::copy_file(coral_data + "/radar.timestamps", dir / "radar.timestamps");
  std::ifstream in(coral_data + "/gt/radar_odometry.csv");
  std::string header, row, rest;
  std::getline(in, header);
  std::getline(in, row);
  rest.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  std::vector<std::string> f;
  std::stringstream ss(row);
  for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
  ASSERT_GE(f.size(), 10u);
  auto write = [&](const std::string& x) {
    std::ostringstream line;
    for (std::size_t i = 0; i < f.size(); ++i) line << (i ? "," : "") << (i == 2 ? x : f[i]);
    std::ofstream(dir / "gt" / "radar_odometry.csv") << header << "\n"
                                                     << line.str() << "\n"
                                                     << rest;
    return line.str();
  };
  OxfordDataset ds;
  std::string err;
  write(f[2]);
  EXPECT_TRUE(ds.load(dir.string(), &err)) << err;  // the copy as it is loads
  for (const std::string bad : {f[2] + "x", std::string("nan"), std::string("")}) {
    const std::string line = write(bad);
    EXPECT_FALSE(ds.load(dir.string(), &err)) << "x = '" << bad << "'";
    EXPECT_NE(err.find("malformed row '" + line + "'"), std::string::npos) << err;
  }
  fs::remove_all(dir);
}

TEST(OxfordRadar, FeatureCountsInPlausibleBand) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  OxfordDataset ds;
  std::string err;
  ASSERT_TRUE(ds.load(coral_data, &err)) << err;
  const auto feats = extractAll(ds, false);
  for (std::size_t i = 0; i < feats.size(); ++i) {
    const auto& f = feats[i];
    std::printf("scan %zu (%lld): %zu RIP features\n", i, static_cast<long long>(ds.stamps_us[i]),
                f.points.size());
    // Reference code (same k, z_min, min range): about 650-690 per scan.
    EXPECT_GT(f.points.size(), 400u);
    EXPECT_LT(f.points.size(), 1200u);
    for (std::size_t k = 0; k < f.points.size(); ++k) {
      ASSERT_GE(f.points[k].head<2>().norm(), 2.5 - 1e-9);
      ASSERT_GT(f.intensity[k], 70.f);
      ASSERT_GE(f.stamps[k], ds.stamps_us[i] * 1e-6 - 1e-6);
      ASSERT_LE(f.stamps[k], ds.stamps_us[i] * 1e-6 + 0.3);
    }
  }
}

TEST(OxfordRadar, GroundTruthRaisesFeatureMatches) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  OxfordDataset ds;
  std::string err;
  ASSERT_TRUE(ds.load(coral_data, &err)) << err;
  for (bool comp : {false, true}) {
    const auto feats = extractAll(ds, comp);
    for (std::size_t i = 1; i < feats.size(); ++i) {
      const double id =
          matchFraction(feats[i - 1].points, feats[i].points, Eigen::Isometry3d::Identity(), 0.5);
      const double gt = matchFraction(feats[i - 1].points, feats[i].points, ds.T_prev_curr[i], 0.5);
      const double inv =
          matchFraction(feats[i - 1].points, feats[i].points, ds.T_prev_curr[i].inverse(), 0.5);
      std::printf("%s pair %zu: matched within 0.5 m identity %.3f  GT %.3f  inverse GT %.3f\n",
                  comp ? "compensated  " : "uncompensated", i, id, gt, inv);
      EXPECT_GT(gt, id + 0.05) << "pair " << i;
      EXPECT_GT(gt, inv) << "pair " << i;
    }
  }
}

TEST(OxfordRadar, CoralQualityLowestAtGroundTruth) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  OxfordDataset ds;
  std::string err;
  ASSERT_TRUE(ds.load(coral_data, &err)) << err;
  const auto feats = extractAll(ds, true);
  const CoralConfig cfg = radarCoral();
  ASSERT_EQ(cfg.validate(), "");
  std::map<double, int> wins;  // offsets (of 40 per magnitude) scoring worse than GT
  for (std::size_t i = 1; i < feats.size(); ++i) {
    Scan a, b;
    a.points = feats[i - 1].points;
    b.points = feats[i].points;
    auto q = [&](double dx, double dy) {
      // Induced error in the later scan's sensor frame: T_prev_curr * offset.
      const Scan bb = transformScan(b, ds.T_prev_curr[i] * se2(dx, dy, 0.0));
      return computeCoral(a, bb, cfg);
    };
    const CoralResult gt = q(0, 0);
    ASSERT_TRUE(gt.valid) << "pair " << i;
    std::printf("pair %zu: Q_gt %.4f overlap %.3f |", i, gt.quality, gt.overlap);
    for (double e : {0.3, 0.5, 0.7}) {
      for (const auto& d : {std::pair{e, 0.0}, {-e, 0.0}, {0.0, e}, {0.0, -e}}) {
        const CoralResult r = q(d.first, d.second);
        if (e == 0.5) std::printf(" (%+.1f,%+.1f) %.4f", d.first, d.second, r.quality);
        wins[e] += gt.quality < r.quality ? 1 : 0;
        // The paper's medium error (0.5 m): GT must score better in every direction.
        if (e == 0.5) {
          EXPECT_LT(gt.quality, r.quality)
              << "pair " << i << " offset " << d.first << "," << d.second;
        }
      }
    }
    std::printf("\n");
  }
  for (const auto& [e, n] : wins) std::printf("Q_gt < Q_offset at %.1f m: %d / 40\n", e, n);
}
