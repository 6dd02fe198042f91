#include "coral_introspection/config/text_fields.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace coral_introspection {
namespace config {

std::vector<std::string> splitFields(const std::string& text, char separator) {
  std::vector<std::string> out;
  std::size_t begin = 0;
  for (;;) {
    const std::size_t end = text.find(separator, begin);
    out.push_back(text.substr(begin, end == std::string::npos ? std::string::npos : end - begin));
    if (end == std::string::npos) return out;
    begin = end + 1;
  }
}

bool parseInteger(const std::string& text, long min, long max, long* out) {
  // strtol alone would skip leading blanks and take a '+': check the characters first.
  const std::size_t digits = !text.empty() && text[0] == '-' ? 1 : 0;
  if (text.size() == digits || text.find_first_not_of("0123456789", digits) != std::string::npos)
    return false;
  errno = 0;
  const long n = std::strtol(text.c_str(), nullptr, 10);
  if (errno == ERANGE || n < min || n > max) return false;
  *out = n;
  return true;
}

bool parseFiniteNumber(const std::string& text, double* out) {
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(x)) return false;
  *out = x;
  return true;
}

}  // namespace config
}  // namespace coral_introspection
