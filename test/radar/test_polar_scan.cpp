// Polar scan decoders: Oxford raw layout, plain mono8 images, presets, corrupt input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>

#include "coral_introspection/radar/polar_scan.hpp"

using namespace coral_introspection::core;

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
