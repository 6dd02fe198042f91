#!/usr/bin/env bash
# Checks the shared data is there when expected (scripts/ci/check_data.sh), installs what is
# needed, builds the package and every test, then runs
#   1. every test through ctest (gtest of the libraries and the ROS layer, rostest of the
#      nodelet);
#   2. scripts/ci/check_format.sh: every tracked C++ file formatted by .clang-format;
#   3. scripts/ci/mutation_check.sh: one-line bugs (its MUTATIONS list), one at a time in a copy of the sources
#      (its own kept build folder, ${CORAL_WS}_mutation: one library + test rebuild per
#      mutant); fails when a pattern no longer matches exactly once or a mutant survives;
#   4. scripts/ci/check_install.sh: `catkin_make install`, then the nodelet launched from the
#      install space alone answers check_alignment; no eval code in the plugin;
#   5. scripts/ci/test_sanitizers.sh: every gtest built with clang, ASan + UBSan and run once;
#   6. scripts/ci/fuzz.sh: each libFuzzer harness for a fixed number of executions.
# All parts run even when one fails; a summary line per part at the end. Exit code != 0 on
# any failure. Idempotent: installed packages and built objects are reused.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
# Expected but missing shared data fails the real-data tests: say so in a second, before
# installing and building for half an hour (scripts/ci/check_data.sh; a note when not expected).
if ! bash "${CORAL_REPO}/scripts/ci/check_data.sh"; then
  echo "=== test summary"
  echo "  FAIL  shared data (scripts/ci/check_data.sh): nothing built or run"
  exit 1
fi
bash "${CORAL_REPO}/scripts/install_deps.sh"
coral_build tests

results=()
run() {
  local name="$1"
  shift
  if "$@"; then results+=("PASS  ${name}"); else results+=("FAIL  ${name}"); fi
}
# gtests $(nproc) at a time; the rostests alone (their RUN_SERIAL property, CMakeLists.txt).
run "ctest (gtest + rostest)" bash -c \
  "cd '${CORAL_WS}/build/coral_introspection' && ctest -j$(nproc) --output-on-failure --timeout 900"
run "clang-format (scripts/ci/check_format.sh)" bash "${CORAL_REPO}/scripts/ci/check_format.sh"
run "mutation check (scripts/ci/mutation_check.sh)" bash "${CORAL_REPO}/scripts/ci/mutation_check.sh"
run "install space (scripts/ci/check_install.sh)" bash "${CORAL_REPO}/scripts/ci/check_install.sh"
run "ASan + UBSan gtests (scripts/ci/test_sanitizers.sh)" bash "${CORAL_REPO}/scripts/ci/test_sanitizers.sh"
# A short fixed budget per harness (the long runs: scripts/ci/fuzz.sh with its default 10^6).
run "fuzz, ${CORAL_FUZZ_RUNS:-20000} runs per harness (scripts/ci/fuzz.sh)" \
  bash "${CORAL_REPO}/scripts/ci/fuzz.sh" "${CORAL_FUZZ_RUNS:-20000}" polar_rip cloud_conversion coral

echo "=== test summary"
failed=0
for r in "${results[@]}"; do
  echo "  ${r}"
  [[ "${r}" == FAIL* ]] && failed=1
done
exit "${failed}"
