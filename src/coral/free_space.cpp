#include "coral_introspection/coral/free_space.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <unordered_map>
#include <vector>

#include "coral_introspection/coral/beam_spacing.hpp"
#include "coral_introspection/coral/validation.hpp"

namespace coral_introspection {
namespace coral {

std::string FreeSpaceConfig::validate() const {
  return Problems()
      .require(bin_deg > 0.0 && bin_deg <= 10.0, "bin_deg", "in (0, 10] deg", bin_deg)
      .require(margin > 0.0 && margin <= 100.0, "margin", "in (0, 100] m", margin)
      .require(min_tested >= 1, "min_tested", ">= 1", min_tested)
      .require(min_extent >= 0.0 && min_extent <= 100.0, "min_extent",
               "in [0, 100] m (0 = every conflict)", min_extent)
      .str();
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A planar scan coarser than bin_deg would leave every other bin empty, and a point next to an
// empty bin is untested ("unknown"): at 2 deg the term measured nothing at all (no result on
// every ACES candidate, doc/loop_closure.md "Another beam spacing"). Its bins are then 1.1 beam
// steps wide: any interval at least a step wide holds a beam of a fan, and finer bins keep the
// test sharp (the nearest return of three bins is the reference).
double planarBinDeg(const Points& pts, const Vec3& origin, int dimension, double bin_deg) {
  if (dimension != 2) return bin_deg;
  const double step = medianBeamStepDeg(pts, origin);
  return std::isfinite(step) && step > 1.05 * bin_deg ? std::min(10.0, 1.1 * step) : bin_deg;
}

// The nearest return per direction bin of one scan, seen from its sensor.
class RangeImage {
 public:
  RangeImage(const Points& pts, const Vec3& origin, int dimension, double bin_deg)
      : origin_(origin),
        planar_(dimension == 2),
        bin_(planarBinDeg(pts, origin, dimension, bin_deg) * M_PI / 180.0) {
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
  // and the neighbouring bins; false in *tested when any of them saw nothing. *bin: p's
  // bin (el * azimuthBins() + az).
  bool inFreeSpace(const Vec3& p, double margin, bool* tested, int* bin) const {
    *tested = false;
    int az, el;
    double r;
    if (!locate(p, &az, &el, &r)) return false;
    *bin = el * n_az_ + az;
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
  int azimuthBins() const { return n_az_; }

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

// A point of the other scan in the view's free space.
struct Conflict {
  int bin;
  Vec3 p;  // in the view's frame
};

// Conflicts in groups at least min_extent wide. Two conflicts join when their bins touch
// (same or neighbouring azimuth, and elevation in 3D), whatever their ranges (a wall seen at
// a grazing angle jumps by metres from bin to bin), or when they lie within `link` of each
// other (a surface seen from farther away than the view's sensor spreads its points over
// several bins). A group counts when the horizontal (x, y) extent of its points reaches
// min_extent: a person standing where the other scan looked through is a small group, the
// end wall of a slid corridor is not.
int structuralConflicts(std::vector<Conflict> c, int n_az, bool planar, double link,
                        double min_extent) {
  if (min_extent <= 0.0) return static_cast<int>(c.size());
  std::sort(c.begin(), c.end(), [](const Conflict& x, const Conflict& y) { return x.bin < y.bin; });
  const int n = static_cast<int>(c.size());
  std::vector<int> parent(c.size());
  for (int i = 0; i < n; ++i) parent[i] = i;
  std::function<int(int)> root = [&](int i) {
    return parent[i] == i ? i : parent[i] = root(parent[i]);
  };
  auto join = [&](int i, int j) { parent[root(j)] = root(i); };
  auto binsTouch = [&](int a, int b) {
    const int daz = std::abs(a % n_az - b % n_az), del = std::abs(a / n_az - b / n_az);
    return (daz <= 1 || daz == n_az - 1) && (planar ? del == 0 : del <= 1);
  };
  for (int i = 0; i < n; ++i)  // sorted by bin: touching bins lie within one row and a bin
    for (int j = i + 1; j < n && c[j].bin - c[i].bin <= n_az + 1; ++j)
      if (binsTouch(c[i].bin, c[j].bin)) join(i, j);
  std::vector<int> first, last;  // the azimuth wrap: column 0 next to column n_az - 1
  for (int i = 0; i < n; ++i) {
    if (c[i].bin % n_az == 0) first.push_back(i);
    if (c[i].bin % n_az == n_az - 1) last.push_back(i);
  }
  for (int i : first)
    for (int j : last)
      if (binsTouch(c[i].bin, c[j].bin)) join(i, j);
  // Within `link`: a hash grid of cells of that size, each point against its neighbour cells.
  auto cellOf = [&](const Vec3& p) {
    return Eigen::Vector3i(static_cast<int>(std::floor(p.x() / link)),
                           static_cast<int>(std::floor(p.y() / link)),
                           planar ? 0 : static_cast<int>(std::floor(p.z() / link)));
  };
  auto key = [](const Eigen::Vector3i& k) {
    return (static_cast<std::int64_t>(k.x()) * 73856093) ^
           (static_cast<std::int64_t>(k.y()) * 19349663) ^
           (static_cast<std::int64_t>(k.z()) * 83492791);
  };
  std::unordered_map<std::int64_t, std::vector<int>> grid;
  for (int i = 0; i < n; ++i) grid[key(cellOf(c[i].p))].push_back(i);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3i k = cellOf(c[i].p);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = planar ? 0 : -1; dz <= (planar ? 0 : 1); ++dz) {
          const auto it = grid.find(key(k + Eigen::Vector3i(dx, dy, dz)));
          if (it == grid.end()) continue;
          for (int j : it->second)
            if (j > i && (c[i].p - c[j].p).squaredNorm() < link * link) join(i, j);
        }
  }
  std::vector<Eigen::Vector4d> box(c.size(), Eigen::Vector4d(kInf, kInf, -kInf, -kInf));
  std::vector<int> size(c.size(), 0);
  for (int i = 0; i < n; ++i) {
    Eigen::Vector4d& b = box[root(i)];
    b = Eigen::Vector4d(std::min(b[0], c[i].p.x()), std::min(b[1], c[i].p.y()),
                        std::max(b[2], c[i].p.x()), std::max(b[3], c[i].p.y()));
    ++size[root(i)];
  }
  int counted = 0;
  for (int i = 0; i < n; ++i)
    if (size[i] > 0 && std::hypot(box[i][2] - box[i][0], box[i][3] - box[i][1]) >= min_extent)
      counted += size[i];
  return counted;
}

// Points of `other` moved into the view's frame by T, tested against the view's range image.
void countConflicts(const RangeImage& view, const Points& other, const Eigen::Isometry3d& T,
                    const FreeSpaceConfig& cfg, bool planar, int* tested, int* conflicts) {
  *tested = 0;
  std::vector<Conflict> found;
  for (const Vec3& q : other) {
    bool t = false;
    int bin = 0;
    const Vec3 p = T * q;
    if (view.inFreeSpace(p, cfg.margin, &t, &bin)) found.push_back({bin, p});
    *tested += t;
  }
  *conflicts =
      structuralConflicts(std::move(found), view.azimuthBins(), planar, cfg.margin, cfg.min_extent);
}

}  // namespace

FreeSpaceResult freeSpaceConflict(const Points& a, const Vec3& origin_a, const Points& b,
                                  const Vec3& origin_b, const Eigen::Isometry3d& T_a_b,
                                  int dimension, const FreeSpaceConfig& cfg) {
  FreeSpaceResult out;
  int tested[2], conflicts[2];
  const bool planar = dimension == 2;
  countConflicts(RangeImage(a, origin_a, dimension, cfg.bin_deg), b, T_a_b, cfg, planar, &tested[0],
                 &conflicts[0]);
  countConflicts(RangeImage(b, origin_b, dimension, cfg.bin_deg), a, T_a_b.inverse(), cfg, planar,
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

}  // namespace coral
}  // namespace coral_introspection
