#include "coral_introspection/coral/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace coral_introspection {
namespace coral {

namespace {
bool hasNaN(const std::vector<double>& v) {
  return std::any_of(v.begin(), v.end(), [](double x) { return std::isnan(x); });
}
}  // namespace

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  if (hasNaN(v)) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  const double upper = v[mid];
  if (v.size() % 2 == 1) return upper;
  // nth_element leaves the smaller half before mid: its largest is the lower middle value.
  return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + mid));
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  if (hasNaN(v)) return std::numeric_limits<double>::quiet_NaN();
  q = std::clamp(q, 0.0, 1.0);
  const std::size_t k = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5);
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

}  // namespace coral
}  // namespace coral_introspection
