#include "coral_introspection/eval/tool_args.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

namespace coral_introspection {
namespace core {

std::string ToolArgs::get(const std::string& option, const std::string& fallback) const {
  const auto it = values.find(option);
  return it == values.end() || it->second.empty() ? fallback : it->second.back();
}

bool parseToolArgs(int argc, const char* const* argv, const std::vector<std::string>& options,
                   const std::vector<std::string>& flags, ToolArgs* out, std::string* error) {
  *out = ToolArgs();
  auto known = [](const std::vector<std::string>& names, const std::string& n) {
    return std::find(names.begin(), names.end(), n) != names.end();
  };
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      out->help = true;
    } else if (known(flags, arg)) {
      out->flags.insert(arg);
    } else if (known(options, arg)) {
      if (i + 1 >= argc) {
        *error = "missing value after " + arg;
        return false;
      }
      out->values[arg].push_back(argv[++i]);
    } else {
      *error = "unknown argument " + arg;
      return false;
    }
  }
  return true;
}

int toolError(const char* tool, const std::string& message, const char* usage) {
  std::fprintf(stderr, "%s: %s\n%s\n", tool, message.c_str(), usage);
  return 2;
}

bool positiveInt(const ToolArgs& args, const std::string& option, int fallback, int* out,
                 std::string* error) {
  if (!args.has(option)) {
    *out = fallback;
    return true;
  }
  const std::string v = args.get(option);
  char* end = nullptr;
  const long n = std::strtol(v.c_str(), &end, 10);
  if (v.empty() || *end != '\0' || n < 1 || n > 1000000000) {
    *error = option + " must be a positive integer (got '" + v + "')";
    return false;
  }
  *out = static_cast<int>(n);
  return true;
}

}  // namespace core
}  // namespace coral_introspection
