#include "coral_introspection/eval/rio_sequence.hpp"

#include <fstream>
#include <iomanip>
#include <sstream>

namespace coral_introspection {
namespace eval {

bool writeRioSequence(const std::string& path, const RioSequence& seq, std::string* error) {
  std::ofstream out(path);
  if (!out) {
    if (error) *error = "cannot write " + path;
    return false;
  }
  out << std::setprecision(10);
  // Stamps may be absolute (1.6e9 s): fixed nanoseconds, not 10 significant digits.
  auto stamp = [](double t) {
    std::ostringstream s;
    s << std::fixed << std::setprecision(9) << t;
    return s.str();
  };
  out << "# coral_introspection rio sequence: imu / radar / gt / baro lines in time order\n";
  std::size_t i = 0, r = 0, g = 0, b = 0;
  auto next_t = [&](std::size_t k, auto& v) { return k < v.size() ? v[k].t : 1e300; };
  while (i < seq.imu.size() || r < seq.radar.size() || g < seq.ground_truth.size() ||
         b < seq.baro.size()) {
    const double ti = next_t(i, seq.imu), tr = next_t(r, seq.radar),
                 tg = next_t(g, seq.ground_truth), tb = next_t(b, seq.baro);
    if (tb < ti && tb <= tr && tb <= tg) {
      out << "baro " << stamp(seq.baro[b].t) << ' ' << std::setprecision(12) << seq.baro[b].pressure
          << std::setprecision(10) << '\n';
      ++b;
    } else if (ti <= tr && ti <= tg) {
      const rio::ImuSample& s = seq.imu[i++];
      out << "imu " << stamp(s.t) << ' ' << s.acc.transpose() << ' ' << s.gyro.transpose() << '\n';
    } else if (tg <= tr) {
      const StampedPose& p = seq.ground_truth[g++];
      out << "gt " << stamp(p.t) << ' ' << p.p.transpose() << ' ' << p.q.coeffs().transpose()
          << '\n';
    } else {
      const rio::RadarFrame& f = seq.radar[r++];
      out << "radar " << stamp(f.t) << ' ' << f.points.size() << '\n';
      for (std::size_t k = 0; k < f.points.size(); ++k)
        out << f.points[k].transpose() << ' '
            << (k < f.radial_velocity.size() ? f.radial_velocity[k] : 0.0) << ' '
            << (k < f.intensity.size() ? f.intensity[k] : 0.0) << '\n';
    }
  }
  return static_cast<bool>(out);
}

bool readRioSequence(const std::string& path, RioSequence* seq, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    if (error) *error = "cannot read " + path;
    return false;
  }
  *seq = RioSequence();
  std::string line;
  int line_no = 0;
  auto bad = [&](const std::string& why) {
    if (error) *error = path + ":" + std::to_string(line_no) + ": " + why;
    return false;
  };
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string kind;
    s >> kind;
    if (kind == "imu") {
      rio::ImuSample x;
      s >> x.t >> x.acc.x() >> x.acc.y() >> x.acc.z() >> x.gyro.x() >> x.gyro.y() >> x.gyro.z();
      if (!s) return bad("malformed imu line");
      seq->imu.push_back(x);
    } else if (kind == "baro") {
      rio::BaroSample x;
      s >> x.t >> x.pressure;
      if (!s) return bad("malformed baro line");
      seq->baro.push_back(x);
    } else if (kind == "gt") {
      StampedPose p;
      double qx, qy, qz, qw;
      s >> p.t >> p.p.x() >> p.p.y() >> p.p.z() >> qx >> qy >> qz >> qw;
      if (!s) return bad("malformed gt line");
      p.q = rio::Quat(qw, qx, qy, qz).normalized();
      seq->ground_truth.push_back(p);
    } else if (kind == "radar") {
      rio::RadarFrame f;
      std::size_t n = 0;
      s >> f.t >> n;
      if (!s || n > 1000000) return bad("malformed radar line");
      for (std::size_t k = 0; k < n; ++k) {
        if (!std::getline(in, line)) return bad("radar frame ends early");
        ++line_no;
        std::istringstream ps(line);
        rio::Vec3 p;
        double vr, inten;
        ps >> p.x() >> p.y() >> p.z() >> vr >> inten;
        if (!ps) return bad("malformed radar point");
        f.points.push_back(p);
        f.radial_velocity.push_back(vr);
        f.intensity.push_back(inten);
      }
      seq->radar.push_back(std::move(f));
    } else {
      return bad("unknown line kind '" + kind + "'");
    }
  }
  return true;
}

}  // namespace eval
}  // namespace coral_introspection
