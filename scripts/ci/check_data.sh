#!/usr/bin/env bash
# Checks, in a second and before anything is built, that the shared real data every test
# asks for (CORAL_REQUIRE_DATA("<subdir>") in test/) is there and readable. Same rules as
# test/support/test_data.hpp: the data root is $CORAL_DATA_DIR, else ../shared/data beside
# the repository; a missing or unreadable data set is an error when the data is expected
# (CORAL_DATA_DIR set, CI=true|1, a misspelled CORAL_DATA* variable, or the root exists),
# otherwise a note (the real-data tests will skip). Exit code 1 on an error.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"

required=""
if [ -n "${CORAL_DATA_DIR+x}" ]; then
  root="${CORAL_DATA_DIR}"
  required="CORAL_DATA_DIR is set"
else
  root="$(cd "${repo}/.." && pwd)/shared/data"
  typo="$(env | sed -n 's/^\(CORAL_DATA[A-Za-z0-9_]*\)=.*/\1/p' | grep -vx CORAL_DATA_DIR |
    paste -sd, || true)"
  if [ -n "${typo}" ]; then
    echo "[data] ERROR: CORAL_DATA_DIR is not set but ${typo} is (misspelled?)" >&2
    exit 1
  fi
  if [ "${CI:-}" = "true" ] || [ "${CI:-}" = "1" ]; then required="CI is set"; fi
  if [ -z "${required}" ] && [ -d "${root}" ]; then required="the data root ${root} exists"; fi
fi

readable() { [ -d "$1" ] && [ -r "$1" ] && [ -x "$1" ]; }

# The data sets the tests ask for, read from the tests themselves.
mapfile -t sets < <(grep -rhoP 'CORAL_REQUIRE_DATA\("\K[^"]+' "${repo}/test" | sort -u)
missing=()
for s in "${sets[@]}"; do
  readable "${root}/${s}" || missing+=("${s}")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "[data] ${#sets[@]} data sets found under ${root}"
  exit 0
fi
if ! readable "${root}"; then
  msg="data root '${root}' is not a readable directory"
else
  msg="data set(s) missing or unreadable under ${root}: ${missing[*]}"
fi
if [ -n "${required}" ]; then
  echo "[data] ERROR: ${msg} (required: ${required}); set CORAL_DATA_DIR to the shared data" >&2
  exit 1
fi
echo "[data] note: ${msg}; the real-data tests will skip"
