#!/usr/bin/env bash
# Builds the gtest suite and the libFuzzer harnesses (test/fuzz) with clang,
# AddressSanitizer and UndefinedBehaviorSanitizer (float-cast-overflow included; every
# report aborts) in a separate catkin workspace, $CORAL_WS_SAN (default: ${CORAL_WS}_san),
# then runs every gtest once. rostests are left out: their nodelets are loaded into the
# uninstrumented /usr/lib/nodelet/nodelet binary (and driven by python), which cannot load
# an ASan-instrumented plugin without preloading the runtime into every process.
# Usage: scripts/ci/test_sanitizers.sh [--build-only]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../env.sh"
export CORAL_WS_SAN="${CORAL_WS_SAN:-${CORAL_WS}_san}"

# -O1 -g as the sanitizer docs advise; Debug keeps Eigen's and the STL's assertions on.
# fuzzer-no-link: coverage instrumentation for the fuzz harnesses (harmless in the tests).
SAN_FLAGS="-fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all"
SAN_FLAGS+=" -fno-omit-frame-pointer -fsanitize=fuzzer-no-link"
FUZZERS="fuzz_polar_rip fuzz_cloud_conversion fuzz_coral"

force="$(coral_link_source "${CORAL_WS_SAN}")"
start=$(date +%s)
(
  cd "${CORAL_WS_SAN}"
  # Only the libraries the tests and harnesses link, the tests and the harnesses: no
  # nodelet plugin, nodes or tools (they add build time and nothing runs them here).
  # shellcheck disable=SC2086,SC2046
  catkin_make ${force} $(coral_launcher_args) -DCMAKE_BUILD_TYPE=Debug -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DCMAKE_CXX_FLAGS="${SAN_FLAGS}" -DCMAKE_C_FLAGS="${SAN_FLAGS}" -DCMAKE_CXX_FLAGS_DEBUG="-g -O1" \
    -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" -DCORAL_FUZZ=ON \
    -DPYTHON_EXECUTABLE=/usr/bin/python3 -j"$(nproc)" tests ${FUZZERS}
)
echo "[test_sanitizers] build: $(( $(date +%s) - start )) s"
[ "${1:-}" = "--build-only" ] && exit 0

set +u
# shellcheck disable=SC1091
source "${CORAL_WS_SAN}/devel/setup.bash"
set -u
export ASAN_SYMBOLIZER_PATH="${ASAN_SYMBOLIZER_PATH:-/usr/lib/llvm-14/bin/llvm-symbolizer}"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
start=$(date +%s)
cd "${CORAL_WS_SAN}/build/coral_introspection"
# Every gtest; test_preset_verdicts judges every 16th shared real pair only (all pairs take 35 s
# in Release and more than 22 min under the sanitizers; the Release run judges them all).
CORAL_VERDICT_PAIR_STRIDE="${CORAL_VERDICT_PAIR_STRIDE:-16}" \
  ctest -j"$(nproc)" --output-on-failure --timeout 1800 -R '_gtest_'
echo "[test_sanitizers] gtests under ASan + UBSan: $(( $(date +%s) - start )) s"
