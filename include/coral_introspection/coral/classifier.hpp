// Logistic-regression alignment classifier (paper Sec. III-F, Eq. 9-10).
#pragma once

#include <string>

namespace coral_introspection {
namespace coral {

struct ClassifierConfig {
  // z = beta0 + beta1 x1 + beta2 x2 with x1 = H_joint, x2 = H_sep (Eq. 9). The defaults
  // are a symmetric boundary on Q: z = 3 - 10 (H_joint - H_sep), i.e. aligned while
  // Q < 0.3 nats; train on your own data (coral_train) for a real boundary.
  double beta0 = 3.0;
  double beta1 = -10.0;
  double beta2 = 10.0;
  double threshold = 0.5;  // t_h of Eq. 10: aligned iff p >= t_h

  std::string validate() const;  // empty when valid
};

struct Verdict {
  double probability = 0.0;  // p of Eq. 9 (probability of "aligned")
  bool aligned = false;      // Eq. 10
};

// Numerically stable logistic function 1 / (1 + e^-z).
double sigmoid(double z);

Verdict classify(const ClassifierConfig& cfg, double x1, double x2);

}  // namespace coral
}  // namespace coral_introspection
