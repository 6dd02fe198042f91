// CFEAR-style radar alignment scores P2P, P2L and P2D (paper Sec. V-A b, after CFEAR [1]):
// k-strongest radar points -> grid-based oriented surface points -> residual costs between
// the surface points of two scans. Planar (x, y); z is ignored.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace eval {

struct CfearConfig {
  double resolution = 3.0;  // [m] grid cell size, surface radius and association radius
                            // (Sec. V-A b: "radius = 3 m")
  int min_points = 6;       // points within `resolution` of a cell mean to make a surface
  // P2D: eigenvalues of a surface covariance below this fraction of the largest are raised
  // to it, so line-like surfaces keep a finite inverse.
  double eigen_floor_ratio = 0.01;
  std::string validate() const;  // empty when valid
};

struct SurfacePoint {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  Eigen::Matrix2d cov = Eigen::Matrix2d::Identity();  // regularized sample covariance
  Eigen::Vector2d normal = Eigen::Vector2d::UnitX();  // smallest-eigenvalue direction
  int num_points = 0;
};
using SurfacePoints = std::vector<SurfacePoint, Eigen::aligned_allocator<SurfacePoint>>;

// One quality measure: x1 = sum of residual costs, x2 = correspondences, x3 = sum / count.
struct CfearScore {
  double sum = 0.0;
  double count = 0.0;
  double normalized = 0.0;
};

struct CfearScores {
  bool valid = false;  // at least one correspondence
  CfearScore p2p, p2l, p2d;
};

// Oriented surface points of one scan: mean of each occupied grid cell, then mean,
// covariance and normal of the points within `resolution` of it.
SurfacePoints computeSurfacePoints(const coral::Points& points, const CfearConfig& cfg);

// Applies the planar part of T_dst_src (mean R m + t, covariance R S R^T, normal R n).
SurfacePoints transformSurfacePoints(const SurfacePoints& s, const Eigen::Isometry3d& T_dst_src);

// Squared residuals of a source surface point x against a target surface point.
double p2pCost(const SurfacePoint& target, const Eigen::Vector2d& x);
double p2lCost(const SurfacePoint& target, const Eigen::Vector2d& x);
// r^T Sigma^-1 r with r = x - mean, evaluated as |L^T r|^2 where L L^T = Sigma^-1 (the
// transpose of the Cholesky factor: using L itself would be wrong for a non-diagonal Sigma).
double p2dCost(const SurfacePoint& target, const Eigen::Vector2d& x);

// Scores source surfaces (already in the target's frame) against target surfaces: each
// source surface is associated with the nearest target mean within `resolution`.
CfearScores computeCfearScores(const SurfacePoints& target, const SurfacePoints& source,
                               const CfearConfig& cfg);

}  // namespace eval
}  // namespace coral_introspection
