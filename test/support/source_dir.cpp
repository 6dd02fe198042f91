#include "support/source_dir.hpp"

namespace coral_test {

const std::string& sourceDir() {
  static const std::string dir = CORAL_SOURCE_DIR;
  return dir;
}

}  // namespace coral_test
