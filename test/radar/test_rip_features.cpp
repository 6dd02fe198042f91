// k-strongest masking and RIP features (Alg. 1) on synthetic polar images.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "coral_introspection/radar/polar_scan.hpp"
#include "coral_introspection/radar/rip_features.hpp"

using namespace coral_introspection::coral;
using namespace coral_introspection::radar;

namespace {
// Straightforward k-strongest: every bin >= z_min, strongest first (lower bin on ties).
std::vector<int> bruteKStrongest(const std::vector<uint8_t>& row, int first, int end, int k,
                                 double z_min) {
  std::vector<int> c;
  for (int i = std::max(0, first); i < end; ++i)
    if (row[i] >= z_min) c.push_back(i);
  std::stable_sort(c.begin(), c.end(), [&](int a, int b) { return row[a] > row[b]; });
  if (static_cast<int>(c.size()) > k) c.resize(k);
  std::sort(c.begin(), c.end());
  return c;
}

// Symmetric peak centred on bin b: 90, 130, 180, 130, 90 (region strength 124 at b).
void addPeak(cv::Mat& img, int row, int b, int scale = 0) {
  const int prof[5] = {90, 130, 180, 130, 90};
  for (int j = -2; j <= 2; ++j)
    img.at<uint8_t>(row, b + j) = cv::saturate_cast<uint8_t>(prof[j + 2] + scale);
}

PolarScan decode(const cv::Mat& img, AzimuthDirection dir = AzimuthDirection::kCounterClockwise) {
  PolarImageConfig cfg = PolarImageConfig::mulranCir204();  // 0.0595 m bins
  cfg.num_azimuths = 0;
  cfg.direction = dir;
  PolarScan s;
  std::string err;
  EXPECT_TRUE(decodePolarImage(img, cfg, 50.0, &s, &err)) << err;
  return s;
}

RadarFeatures rip(const PolarScan& s, const RipConfig& cfg = RipConfig()) {
  RadarFeatures f;
  std::string err;
  EXPECT_TRUE(extractRipFeatures(s, cfg, &f, &err)) << err;
  EXPECT_EQ(f.points.size(), f.intensity.size());
  EXPECT_EQ(f.points.size(), f.stamps.size());
  return f;
}
}  // namespace

TEST(KStrongest, KeepsKLargestAtOrAboveZmin) {
  //                         0   1   2   3    4   5   6   7    8   9
  const std::vector<uint8_t> r{100, 90, 80, 120, 69, 70, 95, 110, 85, 200};
  std::vector<int> bins;
  kStrongest(r.data(), 0, 10, 3, 70, &bins);
  EXPECT_EQ(bins, (std::vector<int>{3, 7, 9}));
  // A decreasing start (100, 90, 80) must not evict weaker bins while fewer than k are held.
  kStrongest(r.data(), 0, 10, 5, 70, &bins);
  EXPECT_EQ(bins, (std::vector<int>{0, 3, 6, 7, 9}));
  // Fewer than k qualify: all of them, 70 included (>= z_min), 69 excluded.
  kStrongest(r.data(), 0, 10, 12, 70, &bins);
  EXPECT_EQ(bins, (std::vector<int>{0, 1, 2, 3, 5, 6, 7, 8, 9}));
  kStrongest(r.data(), 0, 10, 12, 70.5, &bins);  // fractional floor: 70 no longer qualifies
  EXPECT_EQ(bins, (std::vector<int>{0, 1, 2, 3, 6, 7, 8, 9}));
  // Range window [first, end).
  kStrongest(r.data(), 4, 9, 12, 70, &bins);
  EXPECT_EQ(bins, (std::vector<int>{5, 6, 7, 8}));
  // All below z_min.
  kStrongest(r.data(), 0, 10, 12, 201, &bins);
  EXPECT_TRUE(bins.empty());
  // Ties at the k-th value: the lower bin wins.
  const std::vector<uint8_t> t{80, 80, 80, 80};
  kStrongest(t.data(), 0, 4, 2, 70, &bins);
  EXPECT_EQ(bins, (std::vector<int>{0, 1}));
}

TEST(KStrongest, MatchesBruteForceOnRandomRows) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> v(0, 255), len(1, 300);
  std::vector<int> bins;
  for (int trial = 0; trial < 400; ++trial) {
    std::vector<uint8_t> row(len(rng));
    for (auto& x : row) x = static_cast<uint8_t>(v(rng) / (trial % 3 + 1));
    const int n = static_cast<int>(row.size());
    const int first = trial % 5, k = 1 + trial % 20;
    for (double z : {0.0, 1.0, 60.0, 70.0, 127.5, 128.0, 129.0, 200.0, 255.0}) {
      kStrongest(row.data(), first, n, k, z, &bins);
      ASSERT_EQ(bins, bruteKStrongest(row, first, n, k, z)) << "trial " << trial << " z " << z;
    }
  }
}

TEST(RipFeatures, RecoversPeaksWithinHalfABin) {
  cv::Mat img(400, 1500, CV_8UC1, cv::Scalar(0));
  const std::vector<std::pair<int, int>> peaks{
      {0, 100}, {37, 412}, {100, 1000}, {250, 77}, {399, 1490}};
  for (auto [row, bin] : peaks) addPeak(img, row, bin);
  const PolarScan s = decode(img);
  const RadarFeatures f = rip(s);
  ASSERT_EQ(f.points.size(), peaks.size());
  for (std::size_t i = 0; i < peaks.size(); ++i) {
    const auto [row, bin] = peaks[i];
    const double range = bin * 0.0595, az = 2.0 * M_PI * row / 400;
    EXPECT_NEAR(f.points[i].head<2>().norm(), range, 0.5 * 0.0595) << i;
    EXPECT_NEAR(std::remainder(std::atan2(f.points[i].y(), f.points[i].x()) - az, 2 * M_PI), 0,
                1e-9)
        << i;
    EXPECT_EQ(f.points[i].z(), 0.0);
    EXPECT_NEAR(f.intensity[i], 124.f, 1e-4);  // (90 + 130 + 180 + 130 + 90) / 5
    EXPECT_NEAR(f.stamps[i], 50.0 + 0.25 * row / 400, 1e-12);
  }
}

TEST(RipFeatures, SpeckleBelowNoiseFloorGivesNothing) {
  cv::Mat img(400, 1000, CV_8UC1);
  cv::randu(img, 0, 70);  // every bin < z_min = 70
  EXPECT_TRUE(rip(decode(img)).points.empty());
  // Isolated strong bins: each passes k-strongest but its region strength (200 / 5 = 40)
  // stays below z_min.
  img.setTo(0);
  for (int r = 0; r < 400; ++r) img.at<uint8_t>(r, 100 + (r * 7) % 800) = 200;
  EXPECT_TRUE(rip(decode(img)).points.empty());
}

// Alg. 1 line 9 keeps a peak only when its region strength S[r] is strictly above z_min:
// a peak whose 2w + 1 = 5 bins average exactly z_min = 70 is noise, one grey level more is not.
TEST(RipFeatures, PeakExactlyAtNoiseFloorIsNotAFeature) {
  cv::Mat img(400, 1000, CV_8UC1, cv::Scalar(0));
  const uint8_t at_floor[5] = {50, 70, 110, 70, 50};  // sum 350: S = 70 = z_min
  const uint8_t above[5] = {50, 70, 111, 70, 50};     // sum 351: S = 70.2
  for (int j = 0; j < 5; ++j) {
    img.at<uint8_t>(10, 298 + j) = at_floor[j];
    img.at<uint8_t>(20, 598 + j) = above[j];
  }
  RipConfig cfg;
  ASSERT_EQ(cfg.z_min, 70.0);
  ASSERT_EQ(cfg.window, 2);
  const RadarFeatures f = rip(decode(img), cfg);
  ASSERT_EQ(f.points.size(), 1u);  // only the peak above the floor, on row 20
  EXPECT_NEAR(f.points[0].head<2>().norm(), 600 * 0.0595, 1e-9);
  EXPECT_NEAR(std::atan2(f.points[0].y(), f.points[0].x()), 2.0 * M_PI * 20 / 400, 1e-9);
  EXPECT_NEAR(f.intensity[0], 70.2f, 1e-4);
  // The floor is a parameter: at z_min = 69 both peaks are features, at 71 neither is.
  cfg.z_min = 69;
  EXPECT_EQ(rip(decode(img), cfg).points.size(), 2u);
  cfg.z_min = 71;
  EXPECT_TRUE(rip(decode(img), cfg).points.empty());
}

TEST(RipFeatures, WidePlateauGivesOneFeature) {
  cv::Mat img(400, 1000, CV_8UC1, cv::Scalar(0));
  img(cv::Rect(300, 10, 40, 1)).setTo(100);  // 40 bins of equal intensity on row 10
  const RadarFeatures f = rip(decode(img));
  ASSERT_EQ(f.points.size(), 1u);
  const double r = f.points[0].head<2>().norm() / 0.0595;
  EXPECT_GE(r, 300 - 0.5);
  EXPECT_LE(r, 339 + 0.5);
  EXPECT_NEAR(f.intensity[0], 100.f, 1e-4);
}

TEST(RipFeatures, FewerThanKAndKLimit) {
  cv::Mat img(400, 1000, CV_8UC1, cv::Scalar(0));
  addPeak(img, 5, 200, 40);  // strongest
  addPeak(img, 5, 500, 20);
  addPeak(img, 5, 800, 0);
  RipConfig cfg;
  EXPECT_EQ(rip(decode(img), cfg).points.size(), 3u);  // 15 masked bins > k = 12 ...
  cfg.k = 20;
  EXPECT_EQ(rip(decode(img), cfg).points.size(), 3u);  // ... or all 15 masked: 3 peaks
  cfg.k = 1;  // only the strongest bin is masked: one feature, at the strongest peak
  const RadarFeatures f = rip(decode(img), cfg);
  ASSERT_EQ(f.points.size(), 1u);
  EXPECT_NEAR(f.points[0].head<2>().norm(), 200 * 0.0595, 1e-9);
  cfg.k = 12;
  cfg.z_min = 250;  // all below z_min
  EXPECT_TRUE(rip(decode(img), cfg).points.empty());
}

TEST(RipFeatures, RangeLimitsAndInvalidRows) {
  cv::Mat img(400, 1000, CV_8UC1, cv::Scalar(0));
  addPeak(img, 1, 30);   // 1.79 m: closer than min_range 2.5 m
  addPeak(img, 2, 60);   // 3.57 m
  addPeak(img, 3, 900);  // 53.6 m
  addPeak(img, 4, 400);  // row 4 flagged invalid below
  PolarScan s = decode(img);
  s.valid[4] = 0;
  RipConfig cfg;
  RadarFeatures f = rip(s, cfg);
  ASSERT_EQ(f.points.size(), 2u);
  EXPECT_NEAR(f.points[0].head<2>().norm(), 60 * 0.0595, 1e-9);
  cfg.max_range = 50.0;
  f = rip(s, cfg);
  ASSERT_EQ(f.points.size(), 1u);
  cfg.min_range = 0.0;
  EXPECT_EQ(rip(s, cfg).points.size(), 2u);
}

TEST(RipFeatures, ClockwiseMirrorsCounterClockwise) {
  cv::Mat img(400, 1000, CV_8UC1, cv::Scalar(0));
  for (int r = 0; r < 400; r += 13) addPeak(img, r, 100 + 2 * r);
  const RadarFeatures a = rip(decode(img, AzimuthDirection::kCounterClockwise));
  const RadarFeatures b = rip(decode(img, AzimuthDirection::kClockwise));
  ASSERT_EQ(a.points.size(), b.points.size());
  ASSERT_GT(a.points.size(), 20u);
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_NEAR(a.points[i].x(), b.points[i].x(), 1e-9);
    EXPECT_NEAR(a.points[i].y(), -b.points[i].y(), 1e-9);  // mirrored about the x axis
  }
}

TEST(RipFeatures, BadConfigOrScanGivesError) {
  RipConfig cfg;
  EXPECT_EQ(cfg.validate(), "");
  cfg.k = 0;
  EXPECT_NE(cfg.validate().find("k must be in [1, 100000] (got 0)"), std::string::npos);
  cfg = RipConfig();
  cfg.z_min = -1;
  EXPECT_NE(cfg.validate().find("z_min"), std::string::npos);
  cfg = RipConfig();
  cfg.window = -1;
  EXPECT_NE(cfg.validate().find("window"), std::string::npos);
  cfg = RipConfig();
  cfg.max_range = 1.0;
  EXPECT_NE(cfg.validate().find("max_range"), std::string::npos);
  RadarFeatures f;
  std::string err;
  cv::Mat img(400, 100, CV_8UC1, cv::Scalar(0));
  PolarScan s = decode(img);
  EXPECT_FALSE(extractRipFeatures(s, cfg, &f, &err));
  EXPECT_NE(err.find("max_range"), std::string::npos) << err;
  s.stamps.pop_back();
  EXPECT_FALSE(extractRipFeatures(s, RipConfig(), &f, &err));
  EXPECT_NE(err.find("sizes"), std::string::npos) << err;
  EXPECT_FALSE(extractRipFeatures(PolarScan(), RipConfig(), &f, &err));
  EXPECT_FALSE(extractRipFeatures(s, RipConfig(), nullptr, &err));
}
