#include "coral_introspection/online/introspector_config.hpp"

namespace coral_introspection {
namespace online {

std::string prefixMessages(const std::string& group, const std::string& messages) {
  std::string out;
  std::size_t start = 0;
  while (start < messages.size()) {
    std::size_t end = messages.find("; ", start);
    if (end == std::string::npos) end = messages.size();
    out += (out.empty() ? "" : "; ") + group + messages.substr(start, end - start);
    start = end + 2;
  }
  return out;
}

namespace {
void add(std::string* out, const std::string& messages) {
  if (messages.empty()) return;
  *out += (out->empty() ? "" : "; ") + messages;
}
}  // namespace

std::string DopplerCheckConfig::validate() const {
  std::string e;
  add(&e, check.validate());
  if (point_covariances) add(&e, noise.validate());
  return e;
}

std::string IntrospectorConfig::validate() const {
  std::string e;
  add(&e, pairing.validate());  // names its parameters itself
  add(&e, prefixMessages("coral/", coral.validate()));
  // The verdict's groups, from its one list (coral::VerdictConfig::problemsByGroup).
  for (const coral::VerdictConfig::GroupProblems& g : verdict.problemsByGroup())
    add(&e, prefixMessages(std::string(g.group) + "/", g.problems));
  add(&e, prefixMessages("motion_compensation/", deskew.validate()));
  if (doppler.enabled) add(&e, prefixMessages("doppler/", doppler.validate()));
  if (calibration.enabled) add(&e, prefixMessages("calibration/", calibration.validate()));
  return e;
}

}  // namespace online
}  // namespace coral_introspection
