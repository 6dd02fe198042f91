#!/usr/bin/env bash
# Streams a lidar frame into CoralNodelet (own roscore, own nodelet manager) and prints
# verdicts/s, latency, drops, TF failures and the manager's memory (coral_stream_bench).
#   scripts/bench/stream_bench.sh [--port 11311] [--config config/lidar_3d.yaml]
#       [--param key:=value ...] -- <coral_stream_bench arguments>
# e.g. scripts/bench/stream_bench.sh -- --cloud ../shared/data/view_of_delft_example/lidar/training/velodyne/00549.bin --rate 10 --duration 60
# Expects a built workspace (coral_build). Everything it starts is stopped on exit.
set -euo pipefail
# shellcheck source-path=SCRIPTDIR source=../ros_session.sh
source "$(dirname "${BASH_SOURCE[0]}")/../ros_session.sh"
port=11311
config="${CORAL_REPO}/config/lidar_3d.yaml"
params=()
while [ $# -gt 0 ]; do
  case "$1" in
    --port) port="$2"; shift 2 ;;
    --config) config="$2"; shift 2 ;;
    --param) params+=("$2"); shift 2 ;;
    --) shift; break ;;
    *) echo "unknown argument $1 (bench arguments go after --)" >&2; exit 2 ;;
  esac
done
session_roscore "${port}"
for p in "${params[@]}"; do rosparam set "/coral/${p%%:=*}" "${p#*:=}"; done
session_bg roslaunch -p "${port}" coral_introspection coral.launch config:="${config}" scan:=/scan \
  fixed_frame:=odom output:=log
rosrun coral_introspection coral_stream_bench --topic /scan --alignment /alignment \
  --pid-of /coral_manager "$@"
