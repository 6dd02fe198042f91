// Callback guard of the nodelets: an exception escaping a callback would kill every nodelet
// in the manager, so each callback body runs through guarded().
#pragma once

#include <exception>
#include <string>

namespace coral_introspection {
namespace ros_adapters {

// Runs f(); an exception of any kind becomes on_error("<what> failed: <message>").
template <class F, class E>
void guarded(const char* what, F&& f, E&& on_error) noexcept {
  try {
    try {
      f();
    } catch (const std::exception& e) {
      on_error(std::string(what) + " failed: " + e.what());
    } catch (...) {
      on_error(std::string(what) + " failed (unknown exception)");
    }
  } catch (...) {  // reporting itself failed (out of memory): nothing sensible left to do
  }
}

}  // namespace ros_adapters
}  // namespace coral_introspection
