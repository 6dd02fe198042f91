// Reading text inputs the same strict way everywhere: the tools' numbers and number lists
// ("--multiples 1.5,2.5,3"), coral_sequence_demo's scan indices ("~step_scans 10,20") and the
// training samples' CSV lines, CARMEN's ROBOTLASER1 fields. A malformed entry is refused by the
// caller with a message, never skipped: "1,2," once read as [1, 2], a list the user did not write.
// ROS-free, no exceptions.
#pragma once

#include <string>
#include <vector>

namespace coral_introspection {
namespace config {

// The fields of `text` between `separator`s, empty ones included, so that a caller can refuse
// them: "1,,2" -> {"1", "", "2"}, "1,2," -> {"1", "2", ""}, "" -> {""} (std::getline drops
// the trailing empty field and yields nothing for "").
std::vector<std::string> splitFields(const std::string& text, char separator);

// `text` as a whole decimal integer in [min, max]: an optional '-' and digits, nothing else
// (" 5", "+5", "5x", "2.5", "" are refused, as is a value out of range). *out is set only on
// success.
bool parseInteger(const std::string& text, long min, long max, long* out);

// `text` as one finite number in strtod syntax ("0.5", "-2", "1e-4"), the whole string: "",
// "0.5x", "nan", "inf" and "1e999" (out of range) are refused. *out is set only on success.
bool parseFiniteNumber(const std::string& text, double* out);

}  // namespace config
}  // namespace coral_introspection
