// Classification metrics for the alignment classifier: accuracy, ROC curve and AUC.
// Convention everywhere: label 1 = aligned (positive), score = probability of aligned.
#pragma once

#include <vector>

namespace coral_introspection {
namespace coral {

struct RocPoint {
  double threshold = 0.0;  // classify positive iff score >= threshold
  double fpr = 0.0;        // false-positive rate
  double tpr = 0.0;        // true-positive rate (recall)
};

// Fraction of samples with (score >= threshold) == (label == 1). With balanced = true
// each class counts half (mean of the two per-class recalls), the paper's "evaluation
// metrics are balanced accordingly" (Sec. V). NaN for empty input; a missing class makes
// the balanced accuracy equal the recall of the present class.
double accuracy(const std::vector<double>& scores, const std::vector<int>& labels, double threshold,
                bool balanced);

// Area under the ROC curve = P(score of a random positive > score of a random negative),
// ties counted 1/2 (Mann-Whitney U / (n_pos n_neg)). NaN when a class is missing.
double auc(const std::vector<double>& scores, const std::vector<int>& labels);

// ROC curve from (0,0) to (1,1): one point per distinct score, thresholds descending.
std::vector<RocPoint> rocCurve(const std::vector<double>& scores, const std::vector<int>& labels);

}  // namespace coral
}  // namespace coral_introspection
