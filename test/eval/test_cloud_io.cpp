// Point cloud / transform / pose-list readers (eval/cloud_io) on files written here with
// known content, and on the shared real data when present.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "coral_introspection/eval/cloud_io.hpp"
#include "support/test_data.hpp"

using namespace coral_introspection::core;
using coral_test::tempPath;

namespace {

void writeText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

}  // namespace

TEST(CloudIo, AsciiPcdWithMixedTypesAndIntensity) {
  const std::string p = tempPath("ascii", ".pcd");
  writeText(p,
            "VERSION 0.7\nFIELDS x y z intensity\nSIZE 4 8 4 2\nTYPE F F F U\nCOUNT 1 1 1 1\n"
            "WIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n"
            "1.5 -2 3 7\n0 0 0 0\n-4.25 1e3 0.5 65535\n");
  LoadedCloud c;
  std::string err;
  ASSERT_TRUE(loadCloud(p, &c, &err)) << err;
  ASSERT_EQ(c.points.size(), 3u);
  ASSERT_EQ(c.intensity.size(), 3u);
  EXPECT_EQ(c.points[0], Vec3(1.5, -2.0, 3.0));
  EXPECT_EQ(c.points[2], Vec3(-4.25, 1000.0, 0.5));
  EXPECT_FLOAT_EQ(c.intensity[0], 7.f);
  EXPECT_FLOAT_EQ(c.intensity[2], 65535.f);
  std::remove(p.c_str());
}

TEST(CloudIo, PcdWithoutIntensityAndWithoutXyz) {
  const std::string p = tempPath("xyz", ".PCD");
  writeText(p,
            "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\n"
            "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n1 2 3\n4 5 6\n");
  LoadedCloud c;
  std::string err;
  ASSERT_TRUE(loadCloud(p, &c, &err)) << err;
  EXPECT_EQ(c.points.size(), 2u);
  EXPECT_TRUE(c.intensity.empty());
  writeText(p,
            "VERSION 0.7\nFIELDS a b\nSIZE 4 4\nTYPE F F\nCOUNT 1 1\nWIDTH 1\nHEIGHT 1\n"
            "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n1 2\n");
  EXPECT_FALSE(loadCloud(p, &c, &err));
  EXPECT_NE(err.find("x, y, z"), std::string::npos) << err;
  std::remove(p.c_str());
}

TEST(CloudIo, KittiBinRecordsAndTruncatedFile) {
  const std::string p = tempPath("kitti", ".bin");
  const float rec[8] = {1.f, 2.f, 3.f, 0.25f, -7.f, 8.5f, -9.f, 1.f};
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(rec), sizeof(rec));
  LoadedCloud c;
  std::string err;
  ASSERT_TRUE(loadCloud(p, &c, &err)) << err;
  ASSERT_EQ(c.points.size(), 2u);
  EXPECT_EQ(c.points[1], Vec3(-7.0, 8.5, -9.0));
  EXPECT_FLOAT_EQ(c.intensity[0], 0.25f);
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(rec), 20);
  EXPECT_FALSE(loadCloud(p, &c, &err));
  EXPECT_NE(err.find("multiple of 16"), std::string::npos) << err;
  std::remove(p.c_str());
}

TEST(CloudIo, UnknownExtensionAndMissingFile) {
  LoadedCloud c;
  std::string err;
  EXPECT_FALSE(loadCloud("/nonexistent/scan.ply", &c, &err));
  EXPECT_NE(err.find("extension"), std::string::npos) << err;
  EXPECT_FALSE(loadCloud("/nonexistent/scan.pcd", &c, &err));
  EXPECT_FALSE(loadCloud("/nonexistent/scan.bin", &c, &err));
}

TEST(CloudIo, TransformFile3x4And4x4) {
  const std::string p = tempPath("T", ".txt");
  // 90 deg about z, translation (1, 2, 3).
  writeText(p, "0 -1 0 1\n1 0 0 2\n0 0 1 3\n");
  Eigen::Isometry3d T;
  std::string err;
  ASSERT_TRUE(readTransformFile(p, &T, &err)) << err;
  EXPECT_TRUE((T * Vec3(1, 0, 0)).isApprox(Vec3(1, 3, 3)));
  writeText(p, "0,-1,0,1\n1,0,0,2\n0,0,1,3\n0,0,0,1\n");
  ASSERT_TRUE(readTransformFile(p, &T, &err)) << err;
  EXPECT_TRUE((T * Vec3(0, 1, 0)).isApprox(Vec3(0, 2, 3)));
  writeText(p, "0 -1 0 1\n1 0 0 2\n0 0 1 3\n0 0 1 1\n");  // bad last row
  EXPECT_FALSE(readTransformFile(p, &T, &err));
  writeText(p, "2 0 0 0\n0 1 0 0\n0 0 1 0\n");  // scale, not a rotation
  EXPECT_FALSE(readTransformFile(p, &T, &err));
  EXPECT_NE(err.find("rotation"), std::string::npos) << err;
  writeText(p, "1 0 0\n0 1 0\n");  // 6 numbers
  EXPECT_FALSE(readTransformFile(p, &T, &err));
  std::remove(p.c_str());
}

TEST(CloudIo, SharedLivoxKeyframesAndPoses) {
  CORAL_REQUIRE_DATA("hku1_livox_keyframes");
  LoadedCloud c;
  std::string err;
  ASSERT_TRUE(loadCloud(coral_data + "/Scans/000000.pcd", &c, &err)) << err;
  EXPECT_EQ(c.points.size(), 3430u);  // the file header says WIDTH 3430
  EXPECT_EQ(c.intensity.size(), 3430u);
  for (const Vec3& p : c.points) ASSERT_LT(p.norm(), 500.0);
  Isometries poses;
  ASSERT_TRUE(readKittiPoses(coral_data + "/optimized_poses.txt", &poses, &err)) << err;
  EXPECT_EQ(poses.size(), 314u);  // one per keyframe
}

TEST(CloudIo, SharedViewOfDelftLidarBin) {
  CORAL_REQUIRE_DATA("view_of_delft_example/lidar/training/velodyne");
  LoadedCloud c;
  std::string err;
  ASSERT_TRUE(loadCloud(coral_data + "/00549.bin", &c, &err)) << err;
  EXPECT_EQ(c.points.size(), 2684352u / 16u);
}
