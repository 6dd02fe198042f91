#include "coral_introspection/core/classifier.hpp"

#include <cmath>
#include <sstream>

namespace coral_introspection {
namespace core {

std::string ClassifierConfig::validate() const {
  std::ostringstream e;
  if (!(std::isfinite(beta0) && std::isfinite(beta1) && std::isfinite(beta2)))
    e << "beta0..beta2 must be finite";
  if (!(threshold > 0.0 && threshold < 1.0)) {
    if (!e.str().empty()) e << "; ";
    e << "threshold must be in (0, 1) (got " << threshold << ")";
  }
  return e.str();
}

double sigmoid(double z) {
  // Eq. 9, written so that neither branch overflows exp().
  if (z >= 0.0) return 1.0 / (1.0 + std::exp(-z));
  const double ez = std::exp(z);
  return ez / (1.0 + ez);
}

Verdict classify(const ClassifierConfig& cfg, double x1, double x2) {
  Verdict v;
  v.probability = sigmoid(cfg.beta0 + cfg.beta1 * x1 + cfg.beta2 * x2);  // Eq. 9
  v.aligned = v.probability >= cfg.threshold;                            // Eq. 10
  return v;
}

}  // namespace core
}  // namespace coral_introspection
