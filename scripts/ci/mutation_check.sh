#!/usr/bin/env bash
# Mutation check: do the tests fail when the code is wrong? Puts one deliberate one-line bug
# at a time into a COPY of the tracked sources (the repository is never modified), builds
# the relevant ROS-free gtests there (plain CMake, -DCORAL_CORE_ONLY=ON, -O1), runs them
# without the shared data (the copy has no ../shared/data) and, when the data is there, with
# it ($CORAL_DATA_DIR, else ../shared/data beside the repository), and prints which tests
# fail. Exit code != 0 when the unmodified copy fails, when a mutation's pattern does not
# match its file exactly once (a stale pattern fails the check, it is never skipped), when
# a mutant does not build, or when a mutant fails no test.
# The copy's build folder is kept between runs (only what a mutation touches is rebuilt);
# scripts/test.sh runs this check after the format check.
# Usage: scripts/ci/mutation_check.sh
#   CORAL_MUTATION_DIR: work folder (default ${CORAL_WS}_mutation, CORAL_WS as in env.sh)
#   CORAL_BUILD_LOCK: lock file (default /tmp/coral_build.lock), held around the base build
#     and around each mutant's mutate-build-test-restore cycle; not taken again when a
#     parent process already holds it (e.g. `flock /tmp/coral_build.lock scripts/test.sh`)
#     or when CORAL_BUILD_LOCK_HELD=1.
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
source "${REPO}/scripts/env.sh"  # system python first, the compiler cache (coral_launcher_args)
WS="${CORAL_WS}"  # env.sh sets it (default ~/.cache/coral_introspection/ws)
WORK="${CORAL_MUTATION_DIR:-${WS}_mutation}"
SRC="${WORK}/coral_introspection"  # no ../shared/data beside it: the data is absent
BUILD="${WORK}/build"
DIRTY="${WORK}/dirty_files"  # copy files whose objects may still be built from a mutant
LOCK="${CORAL_BUILD_LOCK:-/tmp/coral_build.lock}"
DATA="${CORAL_DATA_DIR:-${REPO}/../shared/data}"
[ -d "${DATA}" ] || DATA=""

# name @ file @ perl regex @ replacement (literal) @ test targets. The regex must match its
# file exactly once; the replacement changes that one line.
CORAL_TESTS="test_coral_known_answers test_coral"
MUTATIONS=(
  "min_overlap gate removed@src/coral/coral.cpp@res->overlap < cfg\.min_overlap\)@false)@${CORAL_TESTS}"
  "Doppler covariance propagation (Eq. 11-12) removed@src/radar/doppler_fit.cpp@return sigma_doppler \* sigma_doppler \+ J\.dot\(point_cov \* J\);@return sigma_doppler * sigma_doppler + 0 * J.dot(point_cov * J);@test_doppler_covariance test_doppler"
  "min_neighbours_other default 1@include/coral_introspection/coral/coral.hpp@int min_neighbours_other = 2;@int min_neighbours_other = 1;@${CORAL_TESTS}"
  "min_neighbours_other ignored (1)@include/coral_introspection/coral/coral.hpp@other\.n >= cfg\.min_neighbours_other@other.n >= 1@${CORAL_TESTS}"
  "own and other neighbourhoods swapped (all-points path)@src/coral/coral.cpp@scorePoint\(m_own, m_other, cfg, &pe\);@scorePoint(m_other, m_own, cfg, &pe);@${CORAL_TESTS}"
  "RIP noise floor: peak at z_min kept@src/radar/rip_features.cpp@if \(sr <= s_min\) continue;@if (sr < s_min) continue;@test_rip_features test_polar_scan test_oxford_radar"
  "free-space margin on the wrong side@src/coral/free_space.cpp@return r <= nearest - margin;@return r <= nearest + margin;@test_free_space"
  "constraint without its rotation column@src/coral/constraint.cpp@J << s\.n, k \* \(s\.p - c\)\.cross\(s\.n\);@J << s.n, 0 * (s.p - c).cross(s.n);@test_constraint"
  "refinement walks past its bound@src/coral/refinement.cpp@if \(toleranceSize\(delta, tol\) > bound\) continue;@if (false) continue;@test_refinement"
  "restart check takes a higher Q for a better one@src/coral/restart_check.cpp@return quality < best_q &&@return quality > best_q &&@test_restart_check"
  "registration from the pose never screened@src/coral/restart_check.cpp@b\.size\(\) > restart\.coarse_points && max_size < 1\.0;@b.size() > restart.coarse_points && max_size < 0.0;@test_restart_check"
  "free_space/ not validated at load@src/coral/verdict.cpp@\{\"free_space\", free_space\.validate\(\)\},@{\"free_space\", \"\"},@test_introspector"
  "restart check's full registrations never end heading back@src/coral/restart_check.cpp@dense \? back_at_candidate : no_stop\);@no_stop);@test_restart_check"
  "restart starts never counted with an earlier one@src/coral/restart_check.cpp@< cfg\.coarse_same_within\) return &e;@< 0.0) return &e;@test_restart_check"
  "gate max_quality compared the wrong way@src/coral/verdict.cpp@terms\.quality > gate\.max_quality@terms.quality < gate.max_quality@test_relative_check"
  "registration from the pose accepted past its bound@src/coral/restart_check.cpp@out\.size <= max_size@true@test_restart_check"
  "constraint counts a denser scanner's points whole@src/coral/beam_spacing.cpp@const double share = step / reference_step_deg;@const double share = 1.0;@test_constraint test_beam_spacing"
  "a finer 2D scan is not thinned to the preset's beam spacing@src/coral/beam_spacing.cpp@if \(k < 2\) return in;@if (k < 1000) return in;@test_beam_spacing"
  "free-space bins of 1 deg for a coarser 2D scanner@src/coral/free_space.cpp@step > 1\.05 \* bin_deg \? std::min@step > 1e9 * bin_deg ? std::min@test_free_space"
  "coarse probe's margin never reached@src/coral/verdict.cpp@coarse\.drop\(\) > gate\.coarse_margin;@coarse.drop() > gate.coarse_margin + 1.0;@test_coarse_probe"
  "registered pose's classifier bound ignored@src/coral/verdict.cpp@at_registered\.classifier\.probability >= gate\.registered_min_probability;@true;@test_restart_check"
  "flat-axes bound off by one@src/coral/verdict.cpp@static_cast<int>\(flat\.size\(\)\) > gate\.max_flat_axes@static_cast<int>(flat.size()) >= gate.max_flat_axes@test_relative_check"
  "flat-axes bound counts roll, pitch and z too@src/coral/relative_check.cpp@if \(a == Axis::kX \|\| a == Axis::kY \|\| a == Axis::kYaw\) out\.push_back\(a\);@out.push_back(a);@test_relative_check"
  "max_range never drops a point@include/coral_introspection/coral/point_filter.hpp@if \(max_range <= 0\.0\) return true;@return true;@test_coral_degenerate"
  "coarse probe ignores the registration from the pose@src/coral/coarse_probe.cpp@if \(!r\.registered \|\| r\.registered_size < min_registered_offset\) return r;@if (true) return r;@test_coarse_probe"
  "registered pose probed only from a full tolerance@src/coral/coarse_probe.cpp@r\.registered_size < min_registered_offset\)@r.registered_size < 1.0)@test_coarse_probe"
  "coarse probe judges poses above its band@src/coral/verdict.cpp@return gate\.coarse_below_probability >= 1\.0 \|\| p < gate\.coarse_below_probability;@return true;@test_coarse_probe"
  "planar graph never keeps the linear start's solve@toolbox/src/eval/pose_graph.cpp@if \(linear\.final_cost < res\.final_cost\) \{@if (false) {@test_pose_graph"
  "odometry yaw corrected the wrong way@toolbox/src/eval/odometry_calibration.cpp@AngleAxisd\(-err,@AngleAxisd(err,@test_odometry_calibration"
  "ROBOTLASER1 remission values read as the pose@toolbox/src/eval/carmen_log.cpp@at \+= 1 \+ remissions;@at += 1;@test_pair_datasets"
  "laser beams with times not de-skewed@src/online/introspector.cpp@if \(\(in\.is_radar \|\| in\.point_stamps\) && cfg_\.deskew\.enabled\)@if (in.is_radar && cfg_.deskew.enabled)@test_introspector"
  "PCD VIEWPOINT ignored@toolbox/src/eval/cloud_io.cpp@if \(origin\.head<3>\(\)\.norm\(\) > 1e-6f \|\|@if (false && origin.head<3>().norm() > 1e-6f ||@test_cloud_io"
)

# One check at a time per work folder (fd 8; the build lock is released between mutants).
mkdir -p "${WORK}"
exec 8> "${WORK}.lock"
if ! flock -n 8; then
  echo "[mutation] another mutation check uses ${WORK}: waiting for it"
  flock 8
fi

# --- the shared build lock (fd 9) -----------------------------------------------------
lock_held_by_ancestor() {  # true when a parent process holds the flock on ${LOCK}
  [ -e "${LOCK}" ] && [ -r /proc/locks ] || return 1
  local inode holders pid
  inode=$(stat -Lc %i "${LOCK}")
  holders=$(awk -v ino=":${inode}" '$2 == "FLOCK" && substr($6, length($6) - length(ino) + 1) == ino { print $5 }' /proc/locks)
  [ -n "${holders}" ] || return 1
  pid=${PPID}
  while [ -n "${pid}" ] && [ "${pid}" -gt 1 ]; do
    grep -qx "${pid}" <<< "${holders}" && return 0
    pid=$(awk '{ print $4 }' "/proc/${pid}/stat" 2> /dev/null || true)
  done
  return 1
}
USE_LOCK=1
if [ "${CORAL_BUILD_LOCK_HELD:-}" = 1 ] || lock_held_by_ancestor; then
  USE_LOCK=0
  echo "[mutation] ${LOCK} is held by a parent process: not taken again"
fi
[ "${USE_LOCK}" = 0 ] || exec 9>> "${LOCK}"
lock() { [ "${USE_LOCK}" = 0 ] || flock 9; }
unlock() { [ "${USE_LOCK}" = 0 ] || flock -u 9; }

# --- restore on any exit ---------------------------------------------------------------
ACTIVE=""  # the copy file that holds a mutant right now
restore() {
  if [ -n "${ACTIVE}" ]; then
    cp "${REPO}/${ACTIVE}" "${SRC}/${ACTIVE}"  # new mtime: its objects get rebuilt
    ACTIVE=""
  fi
}
trap 'restore' EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

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
    sort -u | tr '\n' ' ' || true)
  if [ -z "${failed}" ] && ! grep -q "100% tests passed" "${log}"; then
    failed="(ctest failed, see ${log})"
  fi
  echo "${failed:-none}"
}

all_targets=""
for m in "${MUTATIONS[@]}"; do all_targets+=" ${m##*@}"; done
all_targets=$(echo "${all_targets}" | tr ' ' '\n' | sort -u | tr '\n' ' ')
start=$(date +%s)

lock
mkdir -p "${BUILD}"
rm -rf "${SRC}"
mkdir -p "${SRC}"
# The working tree's files (tracked, uncommitted edits and new files not ignored: a tracked
# file may include a new one), with their mtimes, so the kept build folder rebuilds only
# what changed since the last run...
(cd "${REPO}" && git ls-files -z --cached --others --exclude-standard |
  xargs -0 tar --ignore-failed-read -cf - 2> /dev/null) | tar -xf - -C "${SRC}"
# ...and whatever a mutant had been built from when the last run was interrupted.
if [ -s "${DIRTY}" ]; then
  while read -r f; do [ -e "${SRC}/${f}" ] && touch "${SRC}/${f}"; done < "${DIRTY}"
fi
# -O1: each mutation rebuilds what includes the changed file; compiling dominates.
# shellcheck disable=SC2046
cmake -S "${SRC}" -B "${BUILD}" $(coral_launcher_args) -DCORAL_CORE_ONLY=ON -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" > "${WORK}/cmake.log"
# shellcheck disable=SC2086
if ! build ${all_targets}; then
  echo "MUTATION CHECK FAILED: the unmodified sources do not build (${WORK}/build.log)"
  exit 1
fi
rm -f "${DIRTY}"
# shellcheck disable=SC2086
base_none=$(run_tests base_nodata "" ${all_targets})
base_data="-"
# shellcheck disable=SC2086
[ -n "${DATA}" ] && base_data=$(run_tests base_data "${DATA}" ${all_targets})
unlock
if [ "${base_none}" != none ] || { [ "${base_data}" != none ] && [ "${base_data}" != - ]; }; then
  echo "unmodified sources fail: without data: ${base_none}; with data: ${base_data}"
  exit 1
fi

status=0
rows=()
for m in "${MUTATIONS[@]}"; do
  IFS='@' read -r name file pattern replacement targets <<< "${m}"
  label=$(echo "${name}" | tr -c 'A-Za-z0-9' _)
  matches=$(PAT="${pattern}" perl -0777 -ne 'my $n = () = /$ENV{PAT}/g; print $n' "${SRC}/${file}")
  if [ "${matches}" != 1 ]; then
    rows+=("| ${name} | ${file} | PATTERN MATCHES ${matches} TIMES (must be 1): not applied | |")
    status=1
    continue
  fi
  lock
  ACTIVE="${file}"
  echo "${file}" >> "${DIRTY}"
  PAT="${pattern}" REPL="${replacement}" perl -pi -e 's/$ENV{PAT}/$ENV{REPL}/' "${SRC}/${file}"
  changed=$(diff "${REPO}/${file}" "${SRC}/${file}" | grep -c '^>' || true)
  # shellcheck disable=SC2086
  if [ "${changed}" != 1 ]; then
    rows+=("| ${name} | ${file} | mutant changes ${changed} lines (must be 1): not run | |")
    status=1
  elif ! build ${targets}; then
    rows+=("| ${name} | ${file} | DOES NOT BUILD | |")
    status=1
  else
    # shellcheck disable=SC2086
    no_data=$(run_tests "${label}_nodata" "" ${targets})
    with_data="(no data)"
    # shellcheck disable=SC2086
    [ -n "${DATA}" ] && with_data=$(run_tests "${label}_data" "${DATA}" ${targets})
    if [ "${no_data}" = none ] && { [ "${with_data}" = none ] || [ "${with_data}" = "(no data)" ]; }; then
      rows+=("| ${name} | ${targets} | SURVIVED: none | ${with_data} |")
      status=1
    else
      rows+=("| ${name} | ${targets} | ${no_data} | ${with_data} |")
    fi
  fi
  restore  # before the lock is released
  unlock
done
# Leave the copy's build matching the sources.
lock
# shellcheck disable=SC2086
if build ${all_targets}; then rm -f "${DIRTY}"; fi
unlock

echo "=== mutation check ($(($(date +%s) - start)) s; data: ${DATA:-absent})"
echo "| mutation | tests run | failing without data | failing with data |"
echo "|---|---|---|---|"
for r in "${rows[@]}"; do echo "${r}"; done
if [ "${status}" -eq 0 ]; then
  echo "every pattern applied once, every mutation is caught"
else
  echo "MUTATION CHECK FAILED (stale pattern, mutant not built or mutation survived)"
fi
exit "${status}"
