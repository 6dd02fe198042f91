// Shared helpers for config validation and error reporting in the core (no exceptions:
// everything a nodelet callback calls reports errors by value).
#pragma once

#include <sstream>
#include <string>

namespace coral_introspection {
namespace coral {

// Collects "field must be RULE (got VALUE)" messages; str() joins them with "; ".
class Problems {
 public:
  template <class T>
  Problems& require(bool ok, const char* field, const char* rule, const T& value) {
    if (!ok) {
      std::ostringstream s;
      s << field << " must be " << rule << " (got " << value << ")";
      append(s.str());
    }
    return *this;
  }
  // A free-form message when !ok.
  Problems& require(bool ok, const std::string& message) {
    if (!ok) append(message);
    return *this;
  }
  // Messages of a nested config's validate(), prefixed "prefix: " (nothing when empty).
  Problems& nested(const char* prefix, const std::string& messages) {
    if (!messages.empty()) append(std::string(prefix) + ": " + messages);
    return *this;
  }
  const std::string& str() const { return msg_; }

 private:
  void append(const std::string& m) {
    if (!msg_.empty()) msg_ += "; ";
    msg_ += m;
  }
  std::string msg_;
};

// Stores msg in *error (if given) and returns false: `return fail(error, "...");`.
inline bool fail(std::string* error, const std::string& msg) {
  if (error) *error = msg;
  return false;
}

}  // namespace coral
}  // namespace coral_introspection
