#include "coral_introspection/coral/free_space.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace core {

std::string FreeSpaceConfig::validate() const {
  return Problems()
      .require(bin_deg > 0.0 && bin_deg <= 10.0, "free_space bin_deg", "in (0, 10] deg", bin_deg)
      .require(margin > 0.0, "free_space margin", "> 0 m", margin)
      .require(min_tested >= 1, "free_space min_tested", ">= 1", min_tested)
      .str();
}

namespace {

// The nearest return per direction bin of one scan, seen from its sensor.
class RangeImage {
 public:
  RangeImage(const Points& pts, const Vec3& origin, int dimension, double bin_deg)
      : origin_(origin), planar_(dimension == 2), bin_(bin_deg * M_PI / 180.0) {
    n_az_ = static_cast<int>(std::ceil(2.0 * M_PI / bin_));
    n_el_ = planar_ ? 1 : static_cast<int>(std::ceil(M_PI / bin_)) + 1;
    range_.assign(static_cast<std::size_t>(n_az_) * n_el_, std::numeric_limits<float>::infinity());
    for (const Vec3& p : pts) {
      int az, el;
      double r;
      if (!locate(p, &az, &el, &r)) continue;
      float& cell = range_[static_cast<std::size_t>(el) * n_az_ + az];
      cell = std::min(cell, static_cast<float>(r));
    }
  }

  // Whether p (this scan's frame) lies >= margin in front of the nearest return of its bin
  // and the neighbouring bins; false in *tested when any of them saw nothing.
  bool inFreeSpace(const Vec3& p, double margin, bool* tested) const {
    *tested = false;
    int az, el;
    double r;
    if (!locate(p, &az, &el, &r)) return false;
    float nearest = std::numeric_limits<float>::infinity();
    for (int de = planar_ ? 0 : -1; de <= (planar_ ? 0 : 1); ++de) {
      const int e = el + de;
      if (e < 0 || e >= n_el_) return false;  // beyond the poles: unseen
      for (int da = -1; da <= 1; ++da) {
        const int a = (az + da + n_az_) % n_az_;  // azimuth wraps around
        const float cell = range_[static_cast<std::size_t>(e) * n_az_ + a];
        if (!std::isfinite(cell)) return false;  // a direction without a return: unknown
        nearest = std::min(nearest, cell);
      }
    }
    *tested = true;
    return r <= nearest - margin;
  }

 private:
  bool locate(const Vec3& p, int* az, int* el, double* r) const {
    if (!p.allFinite()) return false;
    const Vec3 d = p - origin_;
    *r = planar_ ? d.head<2>().norm() : d.norm();
    if (!(*r > 0.0)) return false;
    *az = std::min(n_az_ - 1, static_cast<int>((std::atan2(d.y(), d.x()) + M_PI) / bin_));
    *el = planar_ ? 0
                  : std::min(n_el_ - 1,
                             static_cast<int>(
                                 (std::asin(std::clamp(d.z() / *r, -1.0, 1.0)) + M_PI / 2) / bin_));
    return true;
  }

  Vec3 origin_;
  bool planar_;
  double bin_;
  int n_az_ = 0, n_el_ = 0;
  std::vector<float> range_;
};

// Points of `other` (already in the view's frame) tested against the view's range image.
void countConflicts(const RangeImage& view, const Points& other, const Eigen::Isometry3d& T,
                    double margin, int* tested, int* conflicts) {
  *tested = *conflicts = 0;
  for (const Vec3& q : other) {
    bool t = false;
    if (view.inFreeSpace(T * q, margin, &t)) ++*conflicts;
    *tested += t;
  }
}

}  // namespace

FreeSpaceResult freeSpaceConflict(const Points& a, const Vec3& origin_a, const Points& b,
                                  const Vec3& origin_b, const Eigen::Isometry3d& T_a_b,
                                  int dimension, const FreeSpaceConfig& cfg) {
  FreeSpaceResult out;
  int tested[2], conflicts[2];
  countConflicts(RangeImage(a, origin_a, dimension, cfg.bin_deg), b, T_a_b, cfg.margin, &tested[0],
                 &conflicts[0]);
  countConflicts(RangeImage(b, origin_b, dimension, cfg.bin_deg), a, T_a_b.inverse(), cfg.margin,
                 &tested[1], &conflicts[1]);
  out.tested = tested[0] + tested[1];
  out.conflicts = conflicts[0] + conflicts[1];
  if (out.tested < cfg.min_tested) return out;
  out.valid = true;
  out.conflict = 0.0;
  for (int s = 0; s < 2; ++s)  // a direction with few tested points cannot outvote the other
    if (tested[s] >= cfg.min_tested / 2 && tested[s] > 0)
      out.conflict = std::max(out.conflict, static_cast<double>(conflicts[s]) / tested[s]);
  return out;
}

}  // namespace core
}  // namespace coral_introspection
