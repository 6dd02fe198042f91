#include "coral_introspection/eval/trajectory_metrics.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace eval {

namespace {
using rio::Mat3;
using rio::Quat;
using rio::Vec3;

double angleDeg(const Quat& q) { return rio::logQ(q).norm() * 180.0 / M_PI; }

// Ground truth at time t (interpolated), false when t is not within max_dt of a gt pose.
bool gtAt(const std::vector<StampedPose>& gt, double t, double max_dt, StampedPose* out) {
  auto it = std::lower_bound(gt.begin(), gt.end(), t,
                             [](const StampedPose& p, double tt) { return p.t < tt; });
  if (it == gt.end()) {
    if (gt.empty() || t - gt.back().t > max_dt) return false;
    *out = gt.back();
    return true;
  }
  if (it == gt.begin()) {
    if (it->t - t > max_dt) return false;
    *out = *it;
    return true;
  }
  const StampedPose &a = *(it - 1), &b = *it;
  if (std::min(t - a.t, b.t - t) > max_dt) return false;
  const double u = (t - a.t) / (b.t - a.t);
  out->t = t;
  out->p = a.p + u * (b.p - a.p);
  out->q = a.q.slerp(u, b.q);
  return true;
}
}  // namespace

TrajectoryErrors trajectoryErrors(const std::vector<StampedPose>& estimate,
                                  const std::vector<StampedPose>& ground_truth, double max_dt,
                                  bool align) {
  TrajectoryErrors e;
  std::vector<StampedPose> est, gt;
  for (const StampedPose& p : estimate) {
    StampedPose g;
    if (gtAt(ground_truth, p.t, max_dt, &g)) est.push_back(p), gt.push_back(g);
  }
  e.pairs = static_cast<int>(est.size());
  if (e.pairs < 2) return e;
  // Umeyama (no scale): R, t minimising sum |gt - (R est + t)|^2.
  coral::Mat3 R = coral::Mat3::Identity();
  coral::Vec3 t = coral::Vec3::Zero();
  if (align) {
    coral::Vec3 me = coral::Vec3::Zero(), mg = coral::Vec3::Zero();
    for (int k = 0; k < e.pairs; ++k) me += est[k].p, mg += gt[k].p;
    me /= e.pairs;
    mg /= e.pairs;
    coral::Mat3 C = coral::Mat3::Zero();
    for (int k = 0; k < e.pairs; ++k) C += (gt[k].p - mg) * (est[k].p - me).transpose();
    Eigen::JacobiSVD<coral::Mat3> svd(C, Eigen::ComputeFullU | Eigen::ComputeFullV);
    coral::Mat3 S = coral::Mat3::Identity();
    if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) S(2, 2) = -1;
    R = svd.matrixU() * S * svd.matrixV().transpose();
    t = mg - R * me;
  }
  const Quat qR(R);
  double st = 0, sr = 0;
  for (int k = 0; k < e.pairs; ++k) {
    st += (R * est[k].p + t - gt[k].p).squaredNorm();
    const double a = angleDeg(gt[k].q.conjugate() * (qR * est[k].q));
    sr += a * a;
  }
  e.ape_trans = std::sqrt(st / e.pairs);
  e.ape_rot_deg = std::sqrt(sr / e.pairs);
  st = sr = 0;
  for (int k = 1; k < e.pairs; ++k) {
    // E = (T_gt,k^-1 T_gt,k+1)^-1 (T_est,k^-1 T_est,k+1)
    const Quat dqe = est[k - 1].q.conjugate() * est[k].q;
    const coral::Vec3 dpe = est[k - 1].q.conjugate() * (est[k].p - est[k - 1].p);
    const Quat dqg = gt[k - 1].q.conjugate() * gt[k].q;
    const coral::Vec3 dpg = gt[k - 1].q.conjugate() * (gt[k].p - gt[k - 1].p);
    st += (dqg.conjugate() * (dpe - dpg)).squaredNorm();
    const double a = angleDeg(dqg.conjugate() * dqe);
    sr += a * a;
  }
  e.rpe_trans = std::sqrt(st / (e.pairs - 1));
  e.rpe_rot_deg = std::sqrt(sr / (e.pairs - 1));
  return e;
}

LoopError loopError(const std::vector<StampedPose>& tr) {
  LoopError e;
  if (tr.size() < 2) return e;
  const coral::Vec3 d = tr.back().p - tr.front().p;
  e.horizontal = d.head<2>().norm();
  e.vertical = d.z();
  auto yaw = [](const Quat& q) { return coral::yawOf(q.toRotationMatrix()); };
  const double yaw0 = yaw(tr.front().q);
  // The start-heading frame: the TI loop's independent end pose is given in it.
  e.x = std::cos(yaw0) * d.x() + std::sin(yaw0) * d.y();
  e.y = -std::sin(yaw0) * d.x() + std::cos(yaw0) * d.y();
  double dy = yaw(tr.back().q) - yaw0;
  dy = std::remainder(dy, 2.0 * M_PI);
  e.yaw_deg = dy * 180.0 / M_PI;
  return e;
}

bool writeTum(const std::string& path, const std::vector<StampedPose>& trajectory,
              std::string* error) {
  std::ofstream out(path);
  if (!out) {
    if (error) *error = "cannot write " + path;
    return false;
  }
  for (const StampedPose& p : trajectory) {
    out << std::fixed << std::setprecision(9) << p.t << std::setprecision(6);
    out << ' ' << p.p.x() << ' ' << p.p.y() << ' ' << p.p.z() << std::setprecision(9) << ' '
        << p.q.x() << ' ' << p.q.y() << ' ' << p.q.z() << ' ' << p.q.w() << '\n';
  }
  return static_cast<bool>(out);
}

bool readTum(const std::string& path, std::vector<StampedPose>* trajectory, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    if (error) *error = "cannot read " + path;
    return false;
  }
  trajectory->clear();
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    StampedPose p;
    double qx, qy, qz, qw;
    if (!(s >> p.t >> p.p.x() >> p.p.y() >> p.p.z() >> qx >> qy >> qz >> qw)) {
      if (error) *error = "malformed TUM line in " + path + ": " + line;
      return false;
    }
    p.q = Quat(qw, qx, qy, qz).normalized();
    trajectory->push_back(p);
  }
  return true;
}

}  // namespace eval
}  // namespace coral_introspection
