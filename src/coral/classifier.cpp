#include "coral_introspection/coral/classifier.hpp"

#include "coral_introspection/coral/validation.hpp"

#include <cmath>

namespace coral_introspection {
namespace coral {

std::string ClassifierConfig::validate() const {
  return Problems()
      .require(std::isfinite(beta0), "beta0", "finite", beta0)
      .require(std::isfinite(beta1), "beta1", "finite", beta1)
      .require(std::isfinite(beta2), "beta2", "finite", beta2)
      // [0.01, 0.99], the dynamic_reconfigure range of classifier_threshold (cfg/Coral.cfg):
      // a threshold within 1 % of 0 or 1 relies on the tails of the logistic model, which
      // training sets of tens to hundreds of pairs do not calibrate.
      .require(threshold >= 0.01 && threshold <= 0.99, "threshold", "in [0.01, 0.99]", threshold)
      .str();
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

}  // namespace coral
}  // namespace coral_introspection
