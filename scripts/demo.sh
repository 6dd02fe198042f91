#!/usr/bin/env bash
# Installs what is needed, builds what the demo runs and runs it:
#   1. CorAl on a built-in synthetic pair (aligned, then with induced offsets): verdicts;
#   2. a simulated drive replayed through the nodelet with injected odometry errors
#      (roslaunch coral_introspection demo.launch): how many were flagged; the summary is
#      printed last, the exit code is coral_sequence_demo's (0 when the drive was replayed and
#      judged; misses and false alarms are results, not failures).
# Extra arguments go to roslaunch (demo.launch args, or e.g. -p 11999 for a private master).
# Idempotent: installed packages and built objects are reused.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
bash "${CORAL_REPO}/scripts/install_deps.sh"
coral_build demo  # only what the demo runs (scripts/test.sh builds everything)
echo "=== CorAl on the built-in synthetic pair"
rosrun coral_introspection coral_demo_pair
if [ -f "${CORAL_REPO}/launch/demo.launch" ]; then
  echo "=== Simulated drive through the nodelet with injected odometry errors"
  # coral_sequence_demo is not `required` here (roslaunch would end with its red "REQUIRED
  # process has died" banner even on exit code 0): it writes "pid <pid>", then its summary
  # and "exit_code <code>" to ${result}; this script then stops roslaunch (SIGINT, as
  # Ctrl-C) and prints the summary last. Its exit code is the node's.
  result_dir=$(mktemp -d "${TMPDIR:-/tmp}/coral_demo.XXXXXX")
  result="${result_dir}/result"
  roslaunch coral_introspection demo.launch end_with_demo:=false result_file:="${result}" "$@" &
  launch_pid=$!
  trap 'kill -INT "${launch_pid}" 2> /dev/null || true; rm -rf "${result_dir}"' EXIT
  launched=$(date +%s)
  while kill -0 "${launch_pid}" 2> /dev/null; do
    grep -q '^exit_code ' "${result}" 2> /dev/null && break
    node_pid=$(sed -n 's/^pid //p' "${result}" 2> /dev/null || true)
    if [ -n "${node_pid}" ]; then
      # The node is gone without a result (crashed, killed): stop waiting.
      kill -0 "${node_pid}" 2> /dev/null || { sleep 0.5 && break; }
    elif [ $(($(date +%s) - launched)) -gt "${CORAL_DEMO_START_TIMEOUT:-120}" ]; then
      echo "coral_sequence_demo did not start within ${CORAL_DEMO_START_TIMEOUT:-120} s" >&2
      break
    fi
    sleep 0.5
  done
  kill -INT "${launch_pid}" 2> /dev/null || true
  wait "${launch_pid}" || true
  trap 'rm -rf "${result_dir}"' EXIT
  code=$(sed -n 's/^exit_code //p' "${result}" 2> /dev/null || true)
  if [ -z "${code}" ]; then
    echo "[demo] FAILED: coral_sequence_demo ended without a result (see the output above)"
    exit 1
  fi
  grep -v '^exit_code ' "${result}"
  exit "${code}"
fi
