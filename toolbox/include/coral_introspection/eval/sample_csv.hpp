// Reading sample files written by writeSamplesCsv (training_report.hpp), and merging the
// shards of a data set (coral_train --shard i/n) or several data sets into one set, so a
// cluster job array or GNU parallel can compute samples and one process fits from them.
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/eval/evaluation.hpp"

namespace coral_introspection {
namespace eval {

// Methods from the <method>/<feature> columns, groups in order of first appearance. False
// with *error (file:line) on a missing file, an unknown layout or a malformed number.
bool readSamplesCsv(const std::string& path, SampleSet* set, std::string* error);

// Appends `part` to `into` (same methods required; an empty `into` takes part's), then
// orders samples by data set (first appearance), pair index, and position within the pair,
// so the merged set does not depend on the order of the shard files. False with *error on
// a method mismatch or a (data set, pair) present in two parts.
bool mergeSampleSets(SampleSet* into, const SampleSet& part, std::string* error);

}  // namespace eval
}  // namespace coral_introspection
