// Output files of the training / evaluation tool: per-sample CSV, classifier YAML that the
// nodelet loads as-is, a Table II-shaped markdown report and ROC curves as a PNG.
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/coral/verdict.hpp"
#include "coral_introspection/eval/evaluation.hpp"

namespace coral_introspection {
namespace eval {

// One line per sample: pair, stamps, offset, dx, dy, dyaw, group, label, the data set (only
// when a sample names one), then every method's features as <method>/<feature> (NaN: no
// value). Returns false with *error if unwritable. Read back with readSamplesCsv.
bool writeSamplesCsv(const std::string& path, const SampleSet& set, std::string* error);

// coral::classifierYaml (coral/verdict.hpp) written to `path`.
bool writeClassifierYaml(const std::string& path, const coral::ClassifierConfig& c,
                         const std::vector<std::string>& comments, std::string* error);

// Markdown: a Table II-shaped "accuracy/AUC" table (methods x groups) followed by a
// detailed table with balanced and plain accuracy, AUC and the counts behind them.
std::string markdownTables(const std::vector<EvaluationRow>& rows,
                           const std::vector<std::string>& groups);

// ROC curves (held-out scores), one panel per group, one colour per method, AUC in the
// legend. Drawn with OpenCV; false with *error when cv::imwrite fails.
bool writeRocPng(const std::string& path, const std::vector<EvaluationRow>& rows,
                 const std::vector<std::string>& groups, std::string* error);

bool writeTextFile(const std::string& path, const std::string& text, std::string* error);

}  // namespace eval
}  // namespace coral_introspection
