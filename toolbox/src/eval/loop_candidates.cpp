#include "coral_introspection/eval/loop_candidates.hpp"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/gicp.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/ndt.h>
#include <pcl/registration/transformation_estimation_2D.h>
#include <pcl/registration/transformation_estimation_point_to_plane.h>
#include <pcl/registration/warp_point_rigid_3d.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>

#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace eval {

std::string LoopCandidateConfig::validate() const {
  return coral::Problems()
      .require(dimension == 2 || dimension == 3, "dimension", "2 or 3", dimension)
      .require(min_index_gap >= 1, "min_index_gap", ">= 1", min_index_gap)
      .require(radius > 0.0, "radius", "> 0 m", radius)
      .require(lookalike_min_distance > radius, "lookalike_min_distance", "> radius",
               lookalike_min_distance)
      .require(max_correspondence > 0.0, "max_correspondence", "> 0 m", max_correspondence)
      .require(max_iterations >= 1, "max_iterations", ">= 1", max_iterations)
      .require(dimension == 3
                   ? (registration == "gicp" || registration == "ndt" || registration == "icp")
                   : (registration == "icp" || registration == "point_to_line"),
               "registration must be gicp, ndt or icp for 3D scans, icp or point_to_line for 2D "
               "scans; got '" +
                   registration + "' for dimension " + std::to_string(dimension))
      .require(ndt_resolution > 0.0, "ndt_resolution", "> 0 m", ndt_resolution)
      .require(false_multiple >= 1.0, "false_multiple", ">= 1", false_multiple)
      .nested("tolerance", tolerance.validate())
      .str();
}

namespace {

pcl::PointCloud<pcl::PointXYZ>::Ptr toPcl(const coral::Points& pts, int dimension) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr c(new pcl::PointCloud<pcl::PointXYZ>);
  c->reserve(pts.size());
  for (const coral::Vec3& p : pts)
    if (p.allFinite())
      c->push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                 dimension == 2 ? 0.f : static_cast<float>(p.z())));
  return c;
}

// A planar scan with each point's line normal (the target's normals are what point-to-line
// ICP measures along): the least direction of the 2D covariance of the point's
// kNormalNeighbours nearest points, all within kNormalRadius; points without them are dropped
// (a point-to-line residual needs a line).
constexpr int kNormalNeighbours = 6;
constexpr double kNormalRadius = 1.0;  // [m]

pcl::PointCloud<pcl::PointNormal>::Ptr withLineNormals(
    const pcl::PointCloud<pcl::PointXYZ>::Ptr& in) {
  pcl::PointCloud<pcl::PointNormal>::Ptr out(new pcl::PointCloud<pcl::PointNormal>);
  if (in->size() < static_cast<std::size_t>(kNormalNeighbours)) return out;
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(in);
  std::vector<int> idx;
  std::vector<float> d2;
  for (const pcl::PointXYZ& p : *in) {
    if (tree.nearestKSearch(p, kNormalNeighbours, idx, d2) < kNormalNeighbours ||
        d2.back() > kNormalRadius * kNormalRadius)
      continue;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (int i : idx) mean += Eigen::Vector2d((*in)[i].x, (*in)[i].y);
    mean /= idx.size();
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (int i : idx) {
      const Eigen::Vector2d d = Eigen::Vector2d((*in)[i].x, (*in)[i].y) - mean;
      cov += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
    const Eigen::Vector2d n = es.eigenvectors().col(0);  // least eigenvalue first
    pcl::PointNormal q;
    q.x = p.x;
    q.y = p.y;
    q.z = 0.f;
    q.normal_x = static_cast<float>(n.x());
    q.normal_y = static_cast<float>(n.y());
    q.normal_z = 0.f;
    out->push_back(q);
  }
  return out;
}

// Runs a PCL registration (GICP or ICP, both pcl::Registration) from T_init; fills converged
// and fitness, returns the final transformation.
template <class Point>
Eigen::Matrix4f align(pcl::Registration<Point, Point>* reg,
                      const typename pcl::PointCloud<Point>::Ptr& target,
                      const typename pcl::PointCloud<Point>::Ptr& source,
                      const Eigen::Isometry3d& T_init, const LoopCandidateConfig& cfg,
                      LoopCandidate* c) {
  reg->setMaxCorrespondenceDistance(cfg.max_correspondence);
  reg->setMaximumIterations(cfg.max_iterations);
  reg->setInputTarget(target);
  reg->setInputSource(source);
  pcl::PointCloud<Point> aligned;
  reg->align(aligned, T_init.matrix().cast<float>());
  c->converged = reg->hasConverged();
  c->fitness = reg->getFitnessScore(cfg.fitness_range);
  return reg->getFinalTransformation();
}

// Pairs (i, j), j - i >= gap, spread evenly over those that pass `keep` (every k-th).
template <class Keep>
std::vector<std::pair<int, int>> spreadPairs(int n, int gap, int max_pairs, Keep keep) {
  std::vector<std::pair<int, int>> all;
  for (int i = 0; i < n; ++i)
    for (int j = i + gap; j < n; ++j)
      if (keep(i, j)) all.emplace_back(i, j);
  if (static_cast<int>(all.size()) <= max_pairs) return all;
  std::vector<std::pair<int, int>> out;
  for (int k = 0; k < max_pairs; ++k)
    out.push_back(all[static_cast<std::size_t>(k) * all.size() / max_pairs]);
  return out;
}

}  // namespace

LoopCandidateConfig evaluationCandidates(int dimension, const coral::ToleranceConfig& tolerance) {
  LoopCandidateConfig c;
  c.dimension = dimension;
  c.tolerance = tolerance;
  if (dimension == 3) {
    c.propose_by_odometry = true;
  } else {
    c.registration = "icp";
    c.min_index_gap = 30;
    c.max_radius_candidates = 300;  // 2D registration is cheap: a graph with many loops
    c.max_lookalike_pairs = 60;
    c.init_offset = 0.5;
    c.init_offset_deg = 10.0;
  }
  return c;
}

bool withinTolerance(double t, double r_deg, const coral::ToleranceConfig& tol) {
  return t < tol.translation && r_deg < tol.rotation_deg;
}

void relativeError(const Eigen::Isometry3d& T_a_b, const Eigen::Isometry3d& T_ref, double* t,
                   double* r_deg) {
  const Eigen::Isometry3d d = T_ref.inverse() * T_a_b;
  *t = d.translation().norm();
  *r_deg = Eigen::AngleAxisd(d.linear()).angle() * 180.0 / M_PI;
}

std::string fitnessCell(double fitness) {
  if (!(fitness < std::numeric_limits<double>::max())) return "inf";
  std::ostringstream out;
  out << fitness;
  return out.str();
}

void registerPair(const coral::Points& a, const coral::Points& b, const Eigen::Isometry3d& T_init,
                  const LoopCandidateConfig& cfg, LoopCandidate* c) {
  const auto target = toPcl(a, cfg.dimension);
  const auto source = toPcl(b, cfg.dimension);
  // PCL's registrations dereference an empty cloud's search tree (a segfault, not an error),
  // and GICP estimates each point's covariance from its 20 nearest neighbours: fewer points
  // are not registered (a keyframe of a blinded sensor is normal input).
  if (target->size() < kMinRegistrationPoints || source->size() < kMinRegistrationPoints) {
    c->T_a_b = T_init;
    c->converged = false;
    c->fitness = std::numeric_limits<double>::max();  // what PCL reports without correspondences
    return;
  }
  Eigen::Matrix4f result;
  if (cfg.dimension == 3 && cfg.registration == "ndt") {
    pcl::NormalDistributionsTransform<pcl::PointXYZ, pcl::PointXYZ> ndt;
    ndt.setResolution(static_cast<float>(cfg.ndt_resolution));
    ndt.setStepSize(0.1);
    ndt.setTransformationEpsilon(0.01);
    result = align<pcl::PointXYZ>(&ndt, target, source, T_init, cfg, c);
  } else if (cfg.dimension == 3 && cfg.registration == "icp") {
    // Point-to-point ICP in 6 DoF with LIO-SAM's loop-closure settings: correspondences
    // within twice its 15 m history search radius, 100 iterations, epsilons 1e-6.
    LoopCandidateConfig lio_sam = cfg;
    lio_sam.max_correspondence = 30.0;
    lio_sam.max_iterations = 100;
    pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
    icp.setTransformationEpsilon(1e-6);
    icp.setEuclideanFitnessEpsilon(1e-6);
    result = align<pcl::PointXYZ>(&icp, target, source, T_init, lio_sam, c);
  } else if (cfg.dimension == 3) {
    pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> gicp;
    result = align<pcl::PointXYZ>(&gicp, target, source, T_init, cfg, c);
  } else if (cfg.registration == "point_to_line") {
    // Point-to-line ICP in the plane (Censi's PL-ICP is what ROS's laser_scan_matcher runs):
    // PCL's point-to-plane estimation with 2D normals, restricted to x, y, yaw by the warp
    // (the normals have no z, so the other three would be unconstrained).
    using PN = pcl::PointNormal;
    pcl::IterativeClosestPointWithNormals<PN, PN> icp;
    auto est = pcl::make_shared<pcl::registration::TransformationEstimationPointToPlane<PN, PN>>();
    est->setWarpFunction(pcl::make_shared<pcl::registration::WarpPointRigid3D<PN, PN>>());
    icp.setTransformationEstimation(est);
    result = align<PN>(&icp, withLineNormals(target), withLineNormals(source), T_init, cfg, c);
  } else {
    pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;  // "icp": point-to-point
    icp.setTransformationEstimation(
        pcl::registration::TransformationEstimation2D<pcl::PointXYZ, pcl::PointXYZ>::Ptr(
            new pcl::registration::TransformationEstimation2D<pcl::PointXYZ, pcl::PointXYZ>));
    result = align<pcl::PointXYZ>(&icp, target, source, T_init, cfg, c);
  }
  c->T_a_b.matrix() = result.cast<double>();
  // Re-orthonormalise the float result.
  c->T_a_b.linear() = Eigen::Quaterniond(c->T_a_b.linear()).normalized().toRotationMatrix();
}

namespace {

// Labels c against the relative pose T_ref: true within the tolerance, false at
// false_multiple tolerances or more; returns whether to keep it (not in the band between,
// unless keep_ambiguous).
bool labelCandidate(const Eigen::Isometry3d& T_ref, const LoopCandidateConfig& cfg,
                    LoopCandidate* c) {
  c->T_ref = T_ref;
  relativeError(c->T_a_b, T_ref, &c->error_translation, &c->error_rotation_deg);
  const coral::ToleranceConfig& t = cfg.tolerance;
  c->is_true = withinTolerance(c->error_translation, c->error_rotation_deg, t);
  const bool is_false = c->error_translation >= cfg.false_multiple * t.translation ||
                        c->error_rotation_deg >= cfg.false_multiple * t.rotation_deg;
  return c->is_true || is_false || cfg.keep_ambiguous;
}

// x, y offset and yaw [deg] as a planar transform.
Eigen::Isometry3d planarOffset(double x, double y, double yaw_deg) {
  Eigen::Isometry3d d = Eigen::Isometry3d::Identity();
  d.translation() << x, y, 0.0;
  d.linear() =
      Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return d;
}

}  // namespace

// Two registrations of one pair ending within this many metres and degrees reached the same
// optimum.
constexpr double kSameMetres = 0.05, kSameDegrees = 0.5;

bool relationRegistrations(const std::vector<TrainingScan>& scans,
                           const std::vector<ScanPair>& pairs, const LoopCandidateConfig& cfg,
                           std::vector<LoopCandidate>* out, std::string* error) {
  if (const std::string e = cfg.validate(); !e.empty()) return coral::fail(error, e);
  if (cfg.init_offset < 0.0)
    return coral::fail(error, "relation registrations need init_offset >= 0");
  out->clear();
  const double o = cfg.init_offset, y = cfg.init_offset_deg;
  const Eigen::Isometry3d offsets[4] = {planarOffset(o, 0, y), planarOffset(-o, 0, -y),
                                        planarOffset(0, o, -y), planarOffset(0, -o, y)};
  const std::size_t n = std::min(pairs.size(), static_cast<std::size_t>(cfg.max_radius_candidates));
  for (std::size_t k = 0; k < n; ++k) {
    const ScanPair& p = pairs[k * pairs.size() / n];
    std::vector<Eigen::Isometry3d> results;  // of this pair: a result reached twice counts once
    for (const Eigen::Isometry3d& d : offsets) {
      LoopCandidate c;
      c.a = p.a;
      c.b = p.b;
      c.source = "relation_icp";
      registerPair(scans[p.a].scan.points, scans[p.b].scan.points, p.T_a_b * d, cfg, &c);
      const bool seen = std::any_of(results.begin(), results.end(), [&](const auto& T) {
        double t, r;
        relativeError(c.T_a_b, T, &t, &r);
        return t < kSameMetres && r < kSameDegrees;
      });
      results.push_back(c.T_a_b);
      if (!seen && labelCandidate(p.T_a_b, cfg, &c)) out->push_back(c);
    }
  }
  return true;
}

namespace {

// Candidates (a) and (b) of a sequence: revisits within cfg.radius in T_near (the poses a back
// end proposes by), registered from init(i, j); look-alike places at least
// cfg.lookalike_min_distance apart in T_far, registered from each of cfg.headings_deg; each
// kept when keep(&c) says so (it may label c).
void proposeCandidates(const std::vector<TrainingScan>& scans, const coral::Isometries& T_near,
                       const coral::Isometries& T_far,
                       const std::function<Eigen::Isometry3d(int, int)>& init,
                       const LoopCandidateConfig& cfg,
                       const std::function<bool(LoopCandidate*)>& keep,
                       std::vector<LoopCandidate>* out) {
  const int n = static_cast<int>(scans.size());
  out->clear();
  auto distIn = [](const coral::Isometries& T, int i, int j) {
    return (T[i].translation() - T[j].translation()).head<2>().norm();
  };
  // (a) revisits within the radius.
  for (const auto& [i, j] :
       spreadPairs(n, cfg.min_index_gap, cfg.max_radius_candidates,
                   [&](int i, int j) { return distIn(T_near, i, j) <= cfg.radius; })) {
    LoopCandidate c;
    c.a = i;
    c.b = j;
    c.source = "radius";
    registerPair(scans[i].scan.points, scans[j].scan.points, init(i, j), cfg, &c);
    if (keep(&c)) out->push_back(c);
  }
  // (b) different places registered from several headings (translation zero).
  for (const auto& [i, j] :
       spreadPairs(n, cfg.min_index_gap, cfg.max_lookalike_pairs,
                   [&](int i, int j) { return distIn(T_far, i, j) >= cfg.lookalike_min_distance; }))
    for (double yaw : cfg.headings_deg) {
      LoopCandidate c;
      c.a = i;
      c.b = j;
      c.source = "lookalike";
      c.init_yaw_deg = yaw;
      registerPair(scans[i].scan.points, scans[j].scan.points, planarOffset(0.0, 0.0, yaw), cfg,
                   &c);
      if (keep(&c)) out->push_back(c);
    }
}

}  // namespace

bool buildLoopCandidates(const std::vector<TrainingScan>& scans,
                         const coral::Isometries& T_world_ref,
                         const coral::Isometries& T_world_odom, const LoopCandidateConfig& cfg,
                         std::vector<LoopCandidate>* out, std::string* error) {
  if (const std::string e = cfg.validate(); !e.empty()) return coral::fail(error, e);
  if (T_world_ref.size() != scans.size() || T_world_odom.size() != scans.size())
    return coral::fail(error, "scans, reference and odometry poses differ in number");
  // Revisits registered from the odometry's relative pose, or from the reference's moved by
  // init_offset; labelled against the reference (the ambiguous band dropped).
  auto init = [&](int i, int j) -> Eigen::Isometry3d {
    if (cfg.init_offset >= 0.0)
      return T_world_ref[i].inverse() * T_world_ref[j] *
             planarOffset(cfg.init_offset, 0.0, cfg.init_offset_deg);
    return T_world_odom[i].inverse() * T_world_odom[j];
  };
  auto label = [&](LoopCandidate* c) {
    return labelCandidate(T_world_ref[c->a].inverse() * T_world_ref[c->b], cfg, c);
  };
  proposeCandidates(scans, cfg.propose_by_odometry ? T_world_odom : T_world_ref, T_world_ref, init,
                    cfg, label, out);
  return true;
}

bool proposeLoopCandidates(const std::vector<TrainingScan>& scans,
                           const coral::Isometries& T_world_odom, const LoopCandidateConfig& cfg,
                           std::vector<LoopCandidate>* out, std::string* error) {
  if (const std::string e = cfg.validate(); !e.empty()) return coral::fail(error, e);
  if (T_world_odom.size() != scans.size())
    return coral::fail(error, "scans and odometry poses differ in number");
  auto init = [&](int i, int j) {
    return Eigen::Isometry3d(T_world_odom[i].inverse() * T_world_odom[j]);
  };
  proposeCandidates(
      scans, T_world_odom, T_world_odom, init, cfg, [](LoopCandidate*) { return true; }, out);
  return true;
}

}  // namespace eval
}  // namespace coral_introspection
