// Polar scan decoders: Oxford raw layout, plain mono8 images, presets, corrupt input, and
// the one-sweep check (corrupt row stamps / encoder values refused, real scans accepted).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>

#include "coral_introspection/eval/oxford_dataset.hpp"
#include "coral_introspection/radar/polar_scan.hpp"
#include "support/test_data.hpp"

using namespace coral_introspection::radar;
using namespace coral_introspection::eval;

namespace {
constexpr int64_t kT0 = 1547131046353776;  // [us]

// An Oxford-layout image: row i stamped kT0 + 625 i us, encoder 14 i + 13, flag 255, and
// range bin j (column 11 + j) = (i + j) % 50.
cv::Mat oxfordImage() {
  cv::Mat img(400, 3779, CV_8UC1);
  for (int i = 0; i < 400; ++i) {
    uint8_t* row = img.ptr<uint8_t>(i);
    const int64_t us = kT0 + 625 * i;
    for (int b = 0; b < 8; ++b) row[b] = static_cast<uint8_t>((us >> (8 * b)) & 0xFF);
    const int enc = 14 * i + 13;
    row[8] = enc & 0xFF;
    row[9] = (enc >> 8) & 0xFF;
    row[10] = 255;
    for (int j = 0; j < 3768; ++j) row[11 + j] = static_cast<uint8_t>((i + j) % 50);
  }
  return img;
}

// Oxford row metadata, little-endian: stamp [us] in cols 0-7, encoder in cols 8-9.
int64_t rowStampUs(const cv::Mat& img, int i) {
  uint64_t us = 0;
  for (int b = 7; b >= 0; --b) us = (us << 8) | img.at<uint8_t>(i, b);
  return static_cast<int64_t>(us);
}
void setRowStampUs(cv::Mat& img, int i, int64_t us) {
  for (int b = 0; b < 8; ++b)
    img.at<uint8_t>(i, b) = static_cast<uint8_t>((static_cast<uint64_t>(us) >> (8 * b)) & 0xFF);
}
void setRowEncoder(cv::Mat& img, int i, int enc) {
  img.at<uint8_t>(i, 8) = static_cast<uint8_t>(enc & 0xFF);
  img.at<uint8_t>(i, 9) = static_cast<uint8_t>((enc >> 8) & 0xFF);
}

// Expects decodeOxfordImage to refuse img with a message containing `why`.
void expectRefused(const cv::Mat& img, const std::string& why, const std::string& what) {
  PolarScan s;
  std::string err;
  EXPECT_FALSE(decodeOxfordImage(img, &s, &err)) << what;
  EXPECT_NE(err.find(why), std::string::npos) << what << ": " << err;
}

// The corruptions of the reliability issue, each applied to a copy of a good image:
// reversed row stamps, one row stamp of 2^62 us (first, middle, last row), every row at the
// same encoder value, plus a backwards encoder step, a half sweep and two turns in one image.
void expectCorruptionsRefused(const cv::Mat& good, const std::string& name) {
  PolarScan ok;
  std::string err;
  ASSERT_TRUE(decodeOxfordImage(good, &ok, &err)) << name << ": " << err;
  cv::Mat img = good.clone();
  for (int i = 0; i < 400; ++i) setRowStampUs(img, i, rowStampUs(good, 399 - i));
  expectRefused(img, "backwards", name + " reversed stamps");
  for (int row : {0, 200, 399}) {
    img = good.clone();
    setRowStampUs(img, row, int64_t{1} << 62);
    expectRefused(img, row == 0 ? "backwards" : "more than one sweep",
                  name + " 2^62 stamp in row " + std::to_string(row));
  }
  img = good.clone();
  setRowStampUs(img, 399, rowStampUs(good, 0) + 400000);  // last row 0.4 s after the first
  expectRefused(img, "more than one sweep", name + " sweep of 0.4 s");
  img = good.clone();
  const int stuck = img.at<uint8_t>(0, 8) | (img.at<uint8_t>(0, 9) << 8);
  for (int i = 0; i < 400; ++i) setRowEncoder(img, i, stuck);
  expectRefused(img, "stuck encoder", name + " stuck encoder");
  img = good.clone();
  good.row(100).colRange(8, 10).copyTo(img.row(101).colRange(8, 10));
  good.row(101).colRange(8, 10).copyTo(img.row(100).colRange(8, 10));
  expectRefused(img, "azimuth jumps", name + " encoder steps back");
  img = good.clone();
  img.rowRange(200, 400).col(10).setTo(0);  // only the first half of the sweep is valid
  expectRefused(img, "cover 0.5", name + " half sweep");
  img = good.clone();
  for (int i = 0; i < 400; ++i) setRowEncoder(img, i, (28 * i + 13) % 5600);  // two turns
  expectRefused(img, "expected one sweep", name + " two turns");
}
}  // namespace

TEST(PolarScan, DecodesOxfordLayout) {
  const cv::Mat img = oxfordImage();
  PolarScan s;
  std::string err;
  ASSERT_TRUE(decodeOxfordImage(img, &s, &err)) << err;
  ASSERT_EQ(s.power.rows, 400);
  ASSERT_EQ(s.power.cols, 3768);
  EXPECT_EQ(s.power.type(), CV_8UC1);
  EXPECT_DOUBLE_EQ(s.range_resolution, 0.0432);
  EXPECT_NEAR(s.stamp, kT0 * 1e-6, 1e-6);
  for (int i : {0, 1, 199, 399}) {
    EXPECT_NEAR(s.stamps[i], (kT0 + 625 * i) * 1e-6, 1e-6) << i;
    EXPECT_NEAR(s.azimuths[i], (14 * i + 13) / 5600.0 * 2.0 * M_PI, 1e-12) << i;
    EXPECT_EQ(s.valid[i], 1);
    EXPECT_EQ(s.power.at<uint8_t>(i, 0), i % 50);  // bin 0 is column 11
    EXPECT_EQ(s.power.at<uint8_t>(i, 3767), (i + 3767) % 50);
  }
}

TEST(PolarScan, OxfordInvalidRowsAreFlagged) {
  cv::Mat img = oxfordImage();
  img.at<uint8_t>(5, 10) = 0;                                  // valid flag cleared
  img.at<uint8_t>(7, 8) = 0xE0, img.at<uint8_t>(7, 9) = 0x15;  // encoder 5600: out of range
  PolarScan s;
  std::string err;
  ASSERT_TRUE(decodeOxfordImage(img, &s, &err)) << err;
  EXPECT_EQ(s.valid[5], 0);
  EXPECT_EQ(s.valid[7], 0);
  EXPECT_EQ(s.valid[6], 1);
  img.col(10).setTo(0);  // no valid row at all
  EXPECT_FALSE(decodeOxfordImage(img, &s, &err));
  EXPECT_NE(err.find("no valid row"), std::string::npos) << err;
}

TEST(PolarScan, OxfordCorruptInputGivesError) {
  PolarScan s;
  std::string err;
  EXPECT_FALSE(decodeOxfordImage(cv::Mat(), &s, &err));
  EXPECT_NE(err.find("empty"), std::string::npos) << err;
  EXPECT_FALSE(decodeOxfordImage(cv::Mat(399, 3779, CV_8UC1, cv::Scalar(255)), &s, &err));
  EXPECT_NE(err.find("400 x 3779"), std::string::npos) << err;
  EXPECT_FALSE(decodeOxfordImage(cv::Mat(400, 3000, CV_8UC1, cv::Scalar(255)), &s, &err));
  EXPECT_NE(err.find("3000"), std::string::npos) << err;
  EXPECT_FALSE(decodeOxfordImage(cv::Mat(400, 3779, CV_16UC1, cv::Scalar(255)), &s, &err));
  EXPECT_NE(err.find("mono8"), std::string::npos) << err;
  EXPECT_FALSE(decodeOxfordImage(cv::Mat(400, 3779, CV_8UC3, cv::Scalar(255)), &s, &err));
  EXPECT_NE(err.find("mono8"), std::string::npos) << err;
  EXPECT_FALSE(decodeOxfordImage(oxfordImage(), nullptr, &err));
  EXPECT_FALSE(loadOxfordScan("/nonexistent/1.png", &s, &err));
  EXPECT_NE(err.find("/nonexistent/1.png"), std::string::npos) << err;
}

TEST(PolarScan, OxfordPngRoundTrip) {
  const cv::Mat img = oxfordImage();
  const std::string path = ::testing::TempDir() + "/coral_oxford_roundtrip.png";
  ASSERT_TRUE(cv::imwrite(path, img));
  PolarScan s;
  std::string err;
  ASSERT_TRUE(loadOxfordScan(path, &s, &err)) << err;
  EXPECT_NEAR(s.stamps[399], (kT0 + 625 * 399) * 1e-6, 1e-6);
  EXPECT_EQ(cv::norm(s.power, img.colRange(11, 3779), cv::NORM_INF), 0.0);
  std::remove(path.c_str());
}

TEST(PolarScan, PresetsAreValid) {
  const auto ox = PolarImageConfig::oxfordCts350x();
  const auto mr = PolarImageConfig::mulranCir204();
  EXPECT_EQ(ox.validate(), "");
  EXPECT_EQ(mr.validate(), "");
  EXPECT_DOUBLE_EQ(ox.range_resolution, 0.0432);
  EXPECT_DOUBLE_EQ(mr.range_resolution, 0.0595);
  EXPECT_EQ(ox.first_data_column, 11);
  EXPECT_EQ(ox.num_azimuths, 400);
  // The Oxford preset on the raw layout gives the same bins and (uniform) azimuths.
  PolarScan a, b;
  std::string err;
  ASSERT_TRUE(decodeOxfordImage(oxfordImage(), &a, &err)) << err;
  ASSERT_TRUE(decodePolarImage(oxfordImage(), ox, 10.0, &b, &err)) << err;
  EXPECT_EQ(cv::norm(a.power, b.power, cv::NORM_INF), 0.0);
  for (int i = 0; i < 400; ++i)
    EXPECT_NEAR(std::remainder(a.azimuths[i] - b.azimuths[i], 2 * M_PI), 13 / 5600.0 * 2 * M_PI,
                1e-9);
}

TEST(PolarScan, PlainImageAzimuthsStampsAndDirection) {
  PolarImageConfig cfg = PolarImageConfig::mulranCir204();
  cfg.azimuth_offset_rad = 0.1;
  cv::Mat img(400, 100, CV_8UC1, cv::Scalar(3));
  PolarScan ccw, cw;
  std::string err;
  ASSERT_TRUE(decodePolarImage(img, cfg, 100.0, &ccw, &err)) << err;
  cfg.direction = AzimuthDirection::kClockwise;
  ASSERT_TRUE(decodePolarImage(img, cfg, 100.0, &cw, &err)) << err;
  EXPECT_EQ(ccw.power.cols, 100);
  EXPECT_DOUBLE_EQ(ccw.range_resolution, 0.0595);
  EXPECT_DOUBLE_EQ(ccw.stamp, 100.0);
  for (int i : {0, 1, 100, 250, 399}) {
    EXPECT_NEAR(std::remainder(ccw.azimuths[i] - (0.1 + 2 * M_PI * i / 400), 2 * M_PI), 0, 1e-12);
    EXPECT_NEAR(std::remainder(cw.azimuths[i] - (0.1 - 2 * M_PI * i / 400), 2 * M_PI), 0, 1e-12);
    EXPECT_NEAR(ccw.stamps[i], 100.0 + 0.25 * i / 400, 1e-12);
    EXPECT_EQ(ccw.valid[i], 1);
  }
}

TEST(PolarScan, PlainImageCorruptInputAndConfig) {
  PolarImageConfig cfg = PolarImageConfig::mulranCir204();
  PolarScan s;
  std::string err;
  EXPECT_FALSE(decodePolarImage(cv::Mat(), cfg, 0.0, &s, &err));
  EXPECT_NE(err.find("empty"), std::string::npos) << err;
  EXPECT_FALSE(decodePolarImage(cv::Mat(400, 10, CV_32FC1), cfg, 0.0, &s, &err));
  EXPECT_NE(err.find("mono8"), std::string::npos) << err;
  EXPECT_FALSE(decodePolarImage(cv::Mat(300, 10, CV_8UC1), cfg, 0.0, &s, &err));
  EXPECT_NE(err.find("300 rows"), std::string::npos) << err;
  EXPECT_FALSE(decodePolarImage(cv::Mat(400, 10, CV_8UC1), cfg, NAN, &s, &err));
  cfg.first_data_column = 10;
  EXPECT_FALSE(decodePolarImage(cv::Mat(400, 10, CV_8UC1), cfg, 0.0, &s, &err));
  EXPECT_NE(err.find("first_data_column"), std::string::npos) << err;
  cfg = PolarImageConfig::mulranCir204();
  cfg.range_resolution = 0.0;
  EXPECT_NE(cfg.validate().find("range_resolution"), std::string::npos);
  EXPECT_FALSE(decodePolarImage(cv::Mat(400, 10, CV_8UC1), cfg, 0.0, &s, &err));
  EXPECT_NE(err.find("range_resolution"), std::string::npos) << err;
  cfg = PolarImageConfig::mulranCir204();
  cfg.num_azimuths = 0;  // any row count
  EXPECT_TRUE(decodePolarImage(cv::Mat(123, 10, CV_8UC1), cfg, 0.0, &s, &err)) << err;
  EXPECT_EQ(s.azimuths.size(), 123u);
  cfg.scan_period = -1;
  EXPECT_NE(cfg.validate().find("scan_period"), std::string::npos);
}

TEST(PolarSweep, SyntheticCorruptRowsAreRefused) {
  expectCorruptionsRefused(oxfordImage(), "synthetic");
}

TEST(PolarSweep, RealOxfordScansPassAndTheirCorruptionsAreRefused) {
  CORAL_REQUIRE_DATA("oxford_radar_tiny");
  OxfordDataset ds;
  std::string err;
  ASSERT_TRUE(ds.load(coral_data, &err)) << err;
  ASSERT_EQ(ds.png_paths.size(), 11u);
  for (const std::string& path : ds.png_paths) {
    PolarScan s;
    EXPECT_TRUE(loadOxfordScan(path, &s, &err)) << err;  // every real sweep passes
  }
  const cv::Mat img = cv::imread(ds.png_paths[3], cv::IMREAD_UNCHANGED);
  expectCorruptionsRefused(img, ds.png_paths[3]);
}

TEST(PolarSweep, InvalidRowsAreIgnoredAndPlainSweepsPass) {
  // Garbage in rows flagged invalid does not matter: only valid rows form the sweep.
  cv::Mat img = oxfordImage();
  for (int row : {3, 150, 399}) {
    img.at<uint8_t>(row, 10) = 0;
    setRowStampUs(img, row, int64_t{1} << 62);
    setRowEncoder(img, row, 7);
  }
  PolarScan s;
  std::string err;
  EXPECT_TRUE(decodeOxfordImage(img, &s, &err)) << err;
  // Plain images get evenly spaced azimuths and stamps: one sweep in either direction.
  PolarImageConfig cfg = PolarImageConfig::mulranCir204();
  for (auto dir : {AzimuthDirection::kCounterClockwise, AzimuthDirection::kClockwise}) {
    cfg.direction = dir;
    ASSERT_TRUE(decodePolarImage(cv::Mat(400, 20, CV_8UC1), cfg, 5.0, &s, &err)) << err;
    EXPECT_TRUE(checkSweep(s, cfg.scan_period, &err)) << err;
    // Stamps one period later than the bound allows: refused.
    EXPECT_FALSE(checkSweep(s, cfg.scan_period / 2, &err));
    EXPECT_NE(err.find("more than one sweep"), std::string::npos) << err;
  }
  s.valid.assign(s.valid.size(), 0);
  EXPECT_FALSE(checkSweep(s, 0.25, &err));
  EXPECT_NE(err.find("no valid row"), std::string::npos) << err;
  s.valid.pop_back();
  EXPECT_FALSE(checkSweep(s, 0.25, &err));
  EXPECT_NE(err.find("sizes"), std::string::npos) << err;
}
