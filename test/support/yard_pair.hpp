// A ray-cast lidar pair in the synthetic structured yard with a known relative pose, and the
// 2D CorAl settings the planar (one-ring) pair is judged with in the verdict and
// self-calibration tests.
#pragma once

#include <random>

#include "coral_introspection/coral/coral.hpp"
#include "coral_introspection/eval/synthetic.hpp"

namespace coral_introspection {
namespace test {

struct YardPair {
  coral::Scan a, b;  // a in its frame (origin 0), b in its own sensor frame
  Eigen::Isometry3d T_a_b = coral::se2(0.6, 0.2, 0.04);
};

// rings 1: a planar scanner (elevation 0). a is taken at T_world_a, b at T_world_a * T_a_b;
// one random stream (seed) for both scans.
inline YardPair yardPair(int rings, unsigned seed = 7,
                         const Eigen::Isometry3d& T_world_a = Eigen::Isometry3d::Identity()) {
  std::mt19937 rng(seed);
  eval::LidarModel lidar;
  lidar.rings = rings;
  if (rings == 1) lidar.v_min_deg = lidar.v_max_deg = 0.0;
  YardPair p;
  const eval::SyntheticScene scene = eval::SyntheticScene::structuredYard();
  p.a.points = eval::simulateScan(scene, T_world_a, lidar, rng);
  p.b.points = eval::simulateScan(scene, T_world_a * p.T_a_b, lidar, rng);
  return p;
}

// 2D CorAl at r = 0.5 m with a determinant floor: a planar scan's neighbourhoods are lines.
inline coral::CoralConfig planarYardCoral() {
  coral::CoralConfig c;
  c.dimension = 2;
  c.radius = 0.5;
  c.epsilon = 1e-4;
  return c;
}

}  // namespace test
}  // namespace coral_introspection
