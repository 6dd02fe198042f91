#!/usr/bin/env bash
# Mutation check: do the tests fail when the code is wrong? Puts one deliberate one-line bug
# at a time into a COPY of the tracked sources (the repository is never modified), builds
# the relevant ROS-free gtests there (plain CMake, -DCORAL_CORE_ONLY=ON), runs them without
# the shared data (the copy has no ../shared/data) and, when the data is there, with it
# ($CORAL_DATA_DIR, else ../shared/data beside the repository), and prints which tests
# fail. Exit code != 0 when the unmodified copy fails or a mutation fails no test.
# Usage: scripts/mutation_check.sh   (CORAL_MUTATION_DIR: work folder, default
#   /tmp/coral_mutation_$USER; CORAL_BUILD_LOCK: lock file held while it runs,
#   default /tmp/coral_build.lock)
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WORK="${CORAL_MUTATION_DIR:-/tmp/coral_mutation_${USER:-$(id -un)}}"
SRC="${WORK}/coral_introspection"  # no ../shared/data beside it: the data is absent
BUILD="${WORK}/build"
LOCK="${CORAL_BUILD_LOCK:-/tmp/coral_build.lock}"
DATA="${CORAL_DATA_DIR:-${REPO}/../shared/data}"
[ -d "${DATA}" ] || DATA=""
if [ -z "${CORAL_MUTATION_LOCKED:-}" ]; then
  # One lock for the whole check: it is mostly compiling (a rebuild per mutation).
  CORAL_MUTATION_LOCKED=1 exec flock "${LOCK}" bash "$0" "$@"
fi

# name @ file @ perl substitution @ test targets. The substitution must change the file
# (a pattern that no longer matches the code is reported, not skipped silently).
CORAL_TESTS="test_coral_known_answers test_coral"
MUTATIONS=(
  "min_overlap gate removed@src/coral/coral.cpp@s/res->overlap < cfg\.min_overlap/false/g; s/ && res->overlap >= cfg\.min_overlap//g@${CORAL_TESTS}"
  "Doppler covariance propagation (Eq. 11-12) removed@src/radar/doppler_fit.cpp@s/return sigma_doppler \* sigma_doppler \+ J\.dot\(o\.cov \* J\);/return sigma_doppler * sigma_doppler + 0 * J.dot(o.cov * J);/@test_doppler_covariance test_doppler"
  "min_neighbours_other default 1@include/coral_introspection/coral/coral.hpp@s/int min_neighbours_other = 2;/int min_neighbours_other = 1;/@${CORAL_TESTS}"
  "min_neighbours_other ignored (1)@include/coral_introspection/coral/coral.hpp@s/other\.n (>=|<) cfg\.min_neighbours_other/other.n \$1 1/g@${CORAL_TESTS}"
  "own and other neighbourhoods swapped@src/coral/coral.cpp@s/scorePoint\(m_own, m_other,/scorePoint(m_other, m_own,/g@${CORAL_TESTS}"
  "RIP noise floor: peak at z_min kept@src/radar/rip_features.cpp@s/if \(sr <= s_min\) continue;/if (sr < s_min) continue;/@test_rip_features test_polar_scan test_oxford_radar"
)

build() {  # build <targets...>
  make -C "${BUILD}" -j"$(nproc)" "$@" > "${WORK}/build.log" 2>&1 ||
    {
      tail -n 30 "${WORK}/build.log"
      return 1
    }
}

# run_tests <label> <data dir or ""> <targets...>: prints the failed gtests (or "none").
run_tests() {
  local label="$1" data="$2"
  shift 2
  local regex
  regex="^($(echo "$@" | tr ' ' '|'))\$"
  local log="${WORK}/ctest_${label}.log"
  (
    cd "${BUILD}"
    unset CORAL_DATA_DIR CI
    [ -n "${data}" ] && export CORAL_DATA_DIR="${data}"
    ctest --output-on-failure -R "${regex}" > "${log}" 2>&1
  ) || true
  local failed
  failed=$(sed -n 's/^\[  FAILED  \] \([A-Za-z0-9_./]*\).*/\1/p' "${log}" | grep -v '^[0-9]*$' |
    sort -u | tr '\n' ' ')
  if [ -z "${failed}" ] && ! grep -q "100% tests passed" "${log}"; then
    failed="(ctest failed, see ${log})"
  fi
  echo "${failed:-none}"
}

rm -rf "${SRC}"
mkdir -p "${SRC}" "${BUILD}"
# The tracked files as they are in the working tree (uncommitted edits included).
(cd "${REPO}" && git ls-files -z | xargs -0 tar -cf - 2> /dev/null) | tar -xf - -C "${SRC}"
# -O1: each mutation rebuilds what includes the changed file; compiling dominates.
cmake -S "${SRC}" -B "${BUILD}" -DCORAL_CORE_ONLY=ON -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" > "${WORK}/cmake.log"

all_targets=""
for m in "${MUTATIONS[@]}"; do all_targets+=" ${m##*@}"; done
all_targets=$(echo "${all_targets}" | tr ' ' '\n' | sort -u | tr '\n' ' ')
start=$(date +%s)
# shellcheck disable=SC2086
build ${all_targets}
status=0
base_none=$(run_tests base_nodata "" ${all_targets})
base_data="-"
[ -n "${DATA}" ] && base_data=$(run_tests base_data "${DATA}" ${all_targets})
if [ "${base_none}" != none ] || [ "${base_data}" != none -a "${base_data}" != - ]; then
  echo "unmodified sources fail: without data: ${base_none}; with data: ${base_data}"
  exit 1
fi

rows=()
for m in "${MUTATIONS[@]}"; do
  IFS='@' read -r name file subst targets <<< "${m}"
  cp "${REPO}/${file}" "${SRC}/${file}"
  perl -pi -e "${subst}" "${SRC}/${file}"
  if cmp -s "${REPO}/${file}" "${SRC}/${file}"; then
    rows+=("| ${name} | ${file} | pattern not found: mutation not applied | |")
    status=1
    continue
  fi
  # shellcheck disable=SC2086
  if ! build ${targets}; then
    rows+=("| ${name} | ${file} | does not build | |")
    status=1
  else
    # shellcheck disable=SC2086
    no_data=$(run_tests "$(echo "${name}" | tr -c 'A-Za-z0-9' _)_nodata" "" ${targets})
    with_data="(no data)"
    # shellcheck disable=SC2086
    [ -n "${DATA}" ] && with_data=$(run_tests "$(echo "${name}" | tr -c 'A-Za-z0-9' _)_data" \
      "${DATA}" ${targets})
    rows+=("| ${name} | ${targets} | ${no_data} | ${with_data} |")
    if [ "${no_data}" = none ] && [ "${with_data}" = none -o "${with_data}" = "(no data)" ]; then
      status=1
    fi
  fi
  cp "${REPO}/${file}" "${SRC}/${file}"  # restore (the copy; the repository is untouched)
done
# Leave the copy's build matching the sources.
# shellcheck disable=SC2086
build ${all_targets} || true

echo "=== mutation check ($(($(date +%s) - start)) s; data: ${DATA:-absent})"
echo "| mutation | tests run | failing without data | failing with data |"
echo "|---|---|---|---|"
for r in "${rows[@]}"; do echo "${r}"; done
[ "${status}" -eq 0 ] && echo "every mutation is caught" || echo "SOME MUTATION SURVIVED"
exit "${status}"
