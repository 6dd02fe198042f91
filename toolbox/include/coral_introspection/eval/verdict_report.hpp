// Report of a verdict evaluation (verdict_evaluation.hpp): markdown tables per method and
// scenario (LODO, per direction, in-data-set, cross-data-set, relative-check hint and
// flatness), a ROC picture, and the preset's tolerance + classifier YAML sections.
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/coral/verdict.hpp"
#include "coral_introspection/eval/verdict_evaluation.hpp"

namespace coral_introspection {
namespace eval {

// `header` lines go first (title, command, data, settings).
std::string verdictMarkdown(const SampleSet& set, const VerdictEvaluation& eval,
                            const VerdictEvalConfig& cfg, const std::vector<std::string>& header);

// Pooled held-out ROC curves of the three methods: one panel per scenario kind present
// ("cv", "cross", "lodo"). False with *error when the PNG cannot be written.
bool writeVerdictRocPng(const std::string& path, const SampleSet& set,
                        const VerdictEvaluation& eval, std::string* error);

// The preset sections a training run decides: tolerance/* and classifier/* (method, the
// fitted betas, threshold, relative margin and flat ratio), loadable into the nodelet's
// private namespace. `comments` become leading # lines.
std::string verdictYaml(const coral::VerdictConfig& v, const std::vector<std::string>& comments);

}  // namespace eval
}  // namespace coral_introspection
