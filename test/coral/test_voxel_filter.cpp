// Input voxel filter: centroids of known voxels, negative coordinates, 2D mode, far points.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>

#include "coral_introspection/coral/voxel_filter.hpp"

using namespace coral_introspection::coral;

namespace {
// Output sorted lexicographically (the filter's order is a hash order).
Points sorted(Points p) {
  std::sort(p.begin(), p.end(), [](const Vec3& a, const Vec3& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  });
  return p;
}
}  // namespace

TEST(VoxelFilter, CentroidOfEachOccupiedVoxel) {
  // Voxel [0, 0.5)^3 holds three points, voxel [-0.5, 0) x [0, 0.5) x [0, 0.5) two.
  const Points in = {Vec3(0.1, 0.1, 0.1), Vec3(0.2, 0.4, 0.3), Vec3(0.45, 0.1, 0.2),
                     Vec3(-0.1, 0.2, 0.3), Vec3(-0.3, 0.4, 0.1)};
  const Points out = sorted(voxelFilter(in, 0.5, 3));
  ASSERT_EQ(out.size(), 2u);
  EXPECT_TRUE(out[0].isApprox(Vec3(-0.2, 0.3, 0.2), 1e-6)) << out[0].transpose();
  EXPECT_TRUE(out[1].isApprox(Vec3(0.25, 0.2, 0.2), 1e-6)) << out[1].transpose();
}

TEST(VoxelFilter, RandomCloudMatchesPerVoxelMeans) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  Points in;
  for (int i = 0; i < 5000; ++i) in.emplace_back(u(rng) + 1000.0, u(rng) - 2000.0, u(rng));
  const double leaf = 0.7;
  // Reference: group by floor(x / leaf) with a std::map.
  std::map<std::array<long, 3>, std::pair<Vec3, int>> ref;
  for (const Vec3& p : in) {
    auto& e = ref[{long(std::floor(p.x() / leaf)), long(std::floor(p.y() / leaf)),
                   long(std::floor(p.z() / leaf))}];
    if (e.second == 0) e.first.setZero();
    e.first += p;
    ++e.second;
  }
  Points expected;
  for (const auto& kv : ref) expected.push_back(kv.second.first / kv.second.second);
  const Points out = sorted(voxelFilter(in, leaf, 3));
  expected = sorted(expected);
  ASSERT_EQ(out.size(), expected.size());
  for (std::size_t i = 0; i < out.size(); ++i) ASSERT_LT((out[i] - expected[i]).norm(), 1e-5) << i;
}

TEST(VoxelFilter, PlanarModeIgnoresZAndAveragesIt) {
  const Points in = {Vec3(0.1, 0.1, 5.0), Vec3(0.2, 0.2, -1.0), Vec3(1.5, 0.1, 0.0)};
  const Points out = sorted(voxelFilter(in, 1.0, 2));
  ASSERT_EQ(out.size(), 2u);
  EXPECT_TRUE(out[0].isApprox(Vec3(0.15, 0.15, 2.0), 1e-6)) << out[0].transpose();
  EXPECT_TRUE(out[1].isApprox(Vec3(1.5, 0.1, 0.0), 1e-6));
}

TEST(VoxelFilter, OffLeafAndFarPointsKeptAsTheyAre) {
  const Points in = {Vec3(0.1, 0.1, 0.1), Vec3(0.11, 0.1, 0.1), Vec3(1e30, 0, 0),
                     Vec3(0, -1e12, 0)};
  EXPECT_EQ(voxelFilter(in, 0.0, 3).size(), in.size());
  const Points out = voxelFilter(in, 0.1, 3);
  ASSERT_EQ(out.size(), 3u);  // the two near points merged, the far ones kept
  EXPECT_EQ(std::count(out.begin(), out.end(), Vec3(1e30, 0, 0)), 1);
  EXPECT_EQ(std::count(out.begin(), out.end(), Vec3(0, -1e12, 0)), 1);
}
