#include "coral_introspection/eval/synthetic.hpp"

#include <cmath>
#include <limits>

namespace coral_introspection {
namespace eval {

namespace {
Rect wall(double x0, double y0, double x1, double y1, double z0, double z1) {
  const coral::Vec3 a(x0, y0, z0), b(x1, y1, z1);
  const coral::Vec3 c = 0.5 * (a + b);
  return {c, coral::Vec3(0.5 * (x1 - x0), 0.5 * (y1 - y0), 0.0),
          coral::Vec3(0.0, 0.0, 0.5 * (z1 - z0))};
}
// Vertical box faces (no top) centred at (cx, cy), half sizes (hx, hy), rotated by yaw.
void box(std::vector<Rect>& out, double cx, double cy, double hx, double hy, double h, double yaw) {
  const coral::Vec3 ex(std::cos(yaw), std::sin(yaw), 0.0), ey(-std::sin(yaw), std::cos(yaw), 0.0);
  const coral::Vec3 c(cx, cy, 0.5 * h - 1.5), hz(0.0, 0.0, 0.5 * h);
  out.push_back({c + hx * ex, hy * ey, hz});
  out.push_back({c - hx * ex, hy * ey, hz});
  out.push_back({c + hy * ey, hx * ex, hz});
  out.push_back({c - hy * ey, hx * ex, hz});
}
}  // namespace

SyntheticScene SyntheticScene::structuredYard() {
  SyntheticScene s;
  const double floor_z = -1.5, top = 3.0;
  s.rects.push_back(
      {coral::Vec3(0, 0, floor_z), coral::Vec3(15, 0, 0), coral::Vec3(0, 10, 0)});  // floor
  s.rects.push_back(wall(-15, -10, 15, -10, floor_z, top));
  s.rects.push_back(wall(-15, 10, 15, 10, floor_z, top));
  s.rects.push_back(wall(-15, -10, -15, 10, floor_z, top));
  s.rects.push_back(wall(15, -10, 15, 10, floor_z, top));
  box(s.rects, 4.0, 3.0, 1.0, 0.6, 2.0, 0.3);
  box(s.rects, -5.0, -4.0, 0.8, 1.5, 1.2, -0.5);
  box(s.rects, 8.0, -5.0, 0.5, 0.5, 3.0, 0.8);
  box(s.rects, -8.0, 5.0, 2.0, 0.4, 2.5, 1.2);
  box(s.rects, 0.5, -6.5, 0.6, 0.6, 1.0, 0.0);
  return s;
}

std::optional<double> SyntheticScene::castRay(const coral::Vec3& o, const coral::Vec3& d,
                                              double max_range) const {
  double best = std::numeric_limits<double>::infinity();
  for (const Rect& r : rects) {
    const coral::Vec3 n = r.half_u.cross(r.half_v);
    const double denom = n.dot(d);
    if (std::abs(denom) < 1e-12) continue;
    const double t = n.dot(r.center - o) / denom;
    if (t <= 1e-6 || t >= best) continue;
    const coral::Vec3 rel = o + t * d - r.center;
    if (std::abs(rel.dot(r.half_u)) <= r.half_u.squaredNorm() &&
        std::abs(rel.dot(r.half_v)) <= r.half_v.squaredNorm())
      best = t;
  }
  if (best <= max_range) return best;
  return std::nullopt;
}

coral::Points simulateScan(const SyntheticScene& scene, const Eigen::Isometry3d& T_world_sensor,
                           const LidarModel& model, std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, model.range_noise);
  std::uniform_real_distribution<double> start(0.0, 2.0 * M_PI / model.azimuths);
  const double az0 = model.random_azimuth_start ? start(rng) : 0.0;
  const coral::Vec3 o = T_world_sensor.translation();
  const coral::Mat3 R = T_world_sensor.linear();
  coral::Points out;
  out.reserve(static_cast<std::size_t>(model.azimuths) * model.rings);
  for (int ring = 0; ring < model.rings; ++ring) {
    const double el =
        model.rings == 1
            ? 0.0
            : (model.v_min_deg + (model.v_max_deg - model.v_min_deg) * ring / (model.rings - 1)) *
                  M_PI / 180.0;
    for (int i = 0; i < model.azimuths; ++i) {
      const double az = az0 + 2.0 * M_PI * i / model.azimuths;
      const coral::Vec3 d_s(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
      const auto range = scene.castRay(o, R * d_s, model.max_range);
      if (!range || *range < model.min_range) continue;
      out.push_back((*range + noise(rng)) * d_s);
    }
  }
  return out;
}

}  // namespace eval
}  // namespace coral_introspection
