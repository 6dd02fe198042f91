#!/usr/bin/env bash
# Runs libFuzzer harnesses of test/fuzz (built by scripts/ci/test_sanitizers.sh with ASan +
# UBSan) for a fixed number of executions each, starting from the committed seed corpus
# test/fuzz/corpus/<harness>/ (read only). New inputs collect in
# $CORAL_WS_SAN/fuzz/<harness>/corpus; a crash, leak, timeout or sanitizer report stops the
# harness, leaves its input there (crash-*, leak-*, timeout-*) and fails the script.
# Usage: scripts/ci/fuzz.sh [RUNS] [HARNESS...]   default: 1000000 runs, every harness
#   (harness = polar_rip | cloud_conversion | coral). CORAL_FUZZ_SEED sets the seed (1);
#   CORAL_FUZZ_SKIP_BUILD=1 uses the harnesses as built (e.g. built under a lock beforehand).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../env.sh"
export CORAL_WS_SAN="${CORAL_WS_SAN:-${CORAL_WS}_san}"
RUNS="${1:-1000000}"
shift || true
HARNESSES=("$@")
[ ${#HARNESSES[@]} -eq 0 ] && HARNESSES=(polar_rip cloud_conversion coral)

if [ -z "${CORAL_FUZZ_SKIP_BUILD:-}" ]; then
  bash "${CORAL_REPO}/scripts/ci/test_sanitizers.sh" --build-only
fi
export ASAN_SYMBOLIZER_PATH="${ASAN_SYMBOLIZER_PATH:-/usr/lib/llvm-14/bin/llvm-symbolizer}"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
status=0
for h in "${HARNESSES[@]}"; do
  bin="${CORAL_WS_SAN}/devel/lib/coral_introspection/fuzz_${h}"
  work="${CORAL_WS_SAN}/fuzz/${h}"
  mkdir -p "${work}/corpus"
  start=$(date +%s)
  log="${work}/last_run.log"
  if "${bin}" -runs="${RUNS}" -seed="${CORAL_FUZZ_SEED:-1}" -max_len=4096 -timeout=10 \
    -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="${work}/" \
    "${work}/corpus" "${CORAL_REPO}/test/fuzz/corpus/${h}" > "${log}" 2>&1; then
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "${log}")
    echo "[fuzz] ${h}: ${execs} executions in $(( $(date +%s) - start )) s, no crash"
  else
    tail -n 60 "${log}"
    echo "[fuzz] ${h}: FAILED after $(( $(date +%s) - start )) s (log ${log}; input in ${work}/)"
    status=1
  fi
done
exit ${status}
