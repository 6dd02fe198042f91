// The barometer part of the window (barometer.hpp): samples kept until a frame uses them,
// each frame's mean height and its bias state, the bias random walk between frames.
#include <cmath>

#include "coral_introspection/rio/barometer.hpp"
#include "coral_introspection/rio/estimator.hpp"
#include "window_frame.hpp"

namespace coral_introspection {
namespace rio {

void Estimator::addBaro(const BaroSample& s) {
  if (!cfg_.barometer.enabled) return;
  if (!std::isfinite(s.t) || !(s.pressure > 0.0) || !std::isfinite(s.pressure) ||
      (!baro_.empty() && s.t <= baro_.back().first)) {
    ++counters_.bad_baro;
    return;
  }
  baro_.emplace_back(s.t, pressureToAltitude(s.pressure));
  // While initialising no frame takes them: keep the last 2 s (more than a frame interval).
  while (baro_.size() > 1 && baro_.front().first < s.t - 2.0) baro_.pop_front();
}

void Estimator::attachBaro(double t_from, const WindowFrame* prev, WindowFrame* f) {
  if (!cfg_.barometer.enabled) return;
  // Mean of the samples in (t_from, t]: h_i at their mean time tau_i; older ones are spent.
  double sum_h = 0.0, sum_t = 0.0;
  int n = 0;
  while (!baro_.empty() && baro_.front().first <= f->t) {
    if (baro_.front().first > t_from) {
      sum_t += baro_.front().first;
      sum_h += baro_.front().second;
      ++n;
    }
    baro_.pop_front();
  }
  f->has_baro = n > 0;
  f->has_baro_bias = f->has_baro || (prev != nullptr && prev->has_baro_bias);
  if (!f->has_baro_bias) return;
  if (f->has_baro) {
    ++counters_.baro_frames;
    f->baro_height = sum_h / n;
    f->baro_dt = sum_t / n - f->t;
    f->baro_sigma = cfg_.barometer.sigma / std::sqrt(static_cast<double>(n));
  }
  // Start value of the bias: the previous frame's, or what makes the first residual zero.
  f->baro_bias[0] = prev != nullptr && prev->has_baro_bias
                        ? prev->baro_bias[0]
                        : f->baro_height - (f->x.pose[2] + f->x.speed_bias[2] * f->baro_dt);
}

bool Estimator::baroWalkFactor(const WindowFrame& prev, const WindowFrame& f,
                               FactorRef* out) const {
  if (!prev.has_baro_bias || !f.has_baro_bias) return false;
  const double sigma = cfg_.barometer.bias_walk * std::sqrt(std::max(f.t - prev.t, 1e-3));
  *out = {std::make_shared<BaroBiasWalkFactor>(sigma),
          nullptr,
          {const_cast<double*>(prev.baro_bias), const_cast<double*>(f.baro_bias)}};
  return true;
}

}  // namespace rio
}  // namespace coral_introspection
