// Order statistics of a sample, for CorAl's median aggregation, the radar front end and the
// tools' reports: one definition, so every figure called "median" means the same thing.
//
// Conventions (test/coral/test_statistics.cpp):
// - An empty sample gives 0, the value every report here prints for "nothing measured";
//   a caller that must tell the two apart checks empty() first.
// - A NaN anywhere in the sample gives NaN: std::nth_element needs a strict weak order,
//   which NaN breaks, and a statistic that silently skipped values would look measured.
// - Both take the sample by value and reorder their copy (O(n), std::nth_element): pass
//   std::move(v) when the caller no longer needs it.
#pragma once

#include <vector>

namespace coral_introspection {
namespace coral {

// The middle value; for an even size the mean of the two middle values.
double median(std::vector<double> v);

// The sample value of rank round(q (n - 1)) in ascending order, q in [0, 1] (clamped):
// always one of the values, never an interpolation. quantile(v, 0.5) is the median for an
// odd size and the upper of the two middle values for an even one (where a robust estimate
// should be a measured value, e.g. a residual or a twist component).
double quantile(std::vector<double> v, double q);

}  // namespace coral
}  // namespace coral_introspection
