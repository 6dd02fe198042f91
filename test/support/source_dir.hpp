// Where the tests' source tree is (symlink-resolved): configs, the README, doc examples and,
// beside it, ../shared/data.
#pragma once

#include <string>

namespace coral_test {

// Defined in source_dir.cpp, the one object compiled with the path (CORAL_SOURCE_DIR): the
// test objects themselves then do not depend on where the clone lives, so a compiler cache
// reuses them when another clone is built (scripts/env.sh, CI).
const std::string& sourceDir();

}  // namespace coral_test
