#include "coral_introspection/coral/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace coral_introspection {
namespace coral {

double accuracy(const std::vector<double>& scores, const std::vector<int>& labels, double threshold,
                bool balanced) {
  const std::size_t n = std::min(scores.size(), labels.size());
  if (n == 0) return std::numeric_limits<double>::quiet_NaN();
  double correct[2] = {0, 0}, count[2] = {0, 0};
  for (std::size_t i = 0; i < n; ++i) {
    const int c = labels[i] == 1 ? 1 : 0;
    count[c] += 1.0;
    if ((scores[i] >= threshold) == (c == 1)) correct[c] += 1.0;
  }
  if (!balanced) return (correct[0] + correct[1]) / static_cast<double>(n);
  if (count[0] == 0.0) return correct[1] / count[1];
  if (count[1] == 0.0) return correct[0] / count[0];
  return 0.5 * (correct[0] / count[0] + correct[1] / count[1]);
}

double auc(const std::vector<double>& scores, const std::vector<int>& labels) {
  const std::size_t n = std::min(scores.size(), labels.size());
  std::vector<std::size_t> idx(n);
  std::iota(idx.begin(), idx.end(), 0);
  std::sort(idx.begin(), idx.end(),
            [&](std::size_t a, std::size_t b) { return scores[a] < scores[b]; });
  // Mann-Whitney: rank sum of the positives with mid-ranks for tied scores (tie = 1/2).
  double rank_sum_pos = 0.0, n_pos = 0.0;
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i;
    while (j < n && scores[idx[j]] == scores[idx[i]]) ++j;
    const double mid_rank = 0.5 * (static_cast<double>(i + 1) + static_cast<double>(j));
    for (std::size_t k = i; k < j; ++k)
      if (labels[idx[k]] == 1) {
        rank_sum_pos += mid_rank;
        n_pos += 1.0;
      }
    i = j;
  }
  const double n_neg = static_cast<double>(n) - n_pos;
  if (n_pos == 0.0 || n_neg == 0.0) return std::numeric_limits<double>::quiet_NaN();
  const double u = rank_sum_pos - n_pos * (n_pos + 1.0) / 2.0;
  return u / (n_pos * n_neg);
}

std::vector<RocPoint> rocCurve(const std::vector<double>& scores, const std::vector<int>& labels) {
  const std::size_t n = std::min(scores.size(), labels.size());
  std::vector<std::size_t> idx(n);
  std::iota(idx.begin(), idx.end(), 0);
  std::sort(idx.begin(), idx.end(),
            [&](std::size_t a, std::size_t b) { return scores[a] > scores[b]; });
  double n_pos = 0.0;
  for (std::size_t i = 0; i < n; ++i) n_pos += labels[i] == 1 ? 1.0 : 0.0;
  const double n_neg = static_cast<double>(n) - n_pos;
  std::vector<RocPoint> roc{{std::numeric_limits<double>::infinity(), 0.0, 0.0}};
  double tp = 0.0, fp = 0.0;
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i;  // tied scores move the curve diagonally in one step
    for (; j < n && scores[idx[j]] == scores[idx[i]]; ++j) (labels[idx[j]] == 1 ? tp : fp) += 1.0;
    roc.push_back({scores[idx[i]], n_neg > 0 ? fp / n_neg : 0.0, n_pos > 0 ? tp / n_pos : 0.0});
    i = j;
  }
  return roc;
}

}  // namespace coral
}  // namespace coral_introspection
