#!/usr/bin/env bash
# Soak: the Oxford radar scans (../shared/data/oxford_radar_tiny) as a rosbag played in a
# loop (`rosbag play -l`, with --clock if asked) through CoralNodelet for a given time;
# coral_stream_bench --monitor prints memory, verdict rate, latency and how many loops were
# judged after their first scan.
#   scripts/soak_oxford.sh [--port 11311] [--duration 1800] [--clock] [--data DIR] [--config FILE]
# (--config: parameter file of the nodelet, default config/radar_oxford.yaml)
# Expects a built workspace (coral_build). Everything it starts is stopped on exit.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
set +u
source "${CORAL_WS}/devel/setup.bash"
set -u
port=11311
duration=1800
clock=""
config="${CORAL_REPO}/config/radar_oxford.yaml"
data="${CORAL_DATA_DIR:-${CORAL_REPO}/../shared/data}/oxford_radar_tiny"
while [ $# -gt 0 ]; do
  case "$1" in
    --port) port="$2"; shift 2 ;;
    --duration) duration="$2"; shift 2 ;;
    --clock) clock="--clock"; shift ;;
    --data) data="$2"; shift 2 ;;
    --config) config="$2"; shift 2 ;;
    *) echo "unknown argument $1" >&2; exit 2 ;;
  esac
done
export ROS_MASTER_URI="http://localhost:${port}"
bag="$(mktemp -d)/oxford.bag"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$(dirname "${bag}")"
}
trap cleanup EXIT
rosrun coral_introspection oxford_to_bag "${data}" "${bag}"
roscore -p "${port}" >/dev/null 2>&1 &
pids+=($!)
until rosparam list >/dev/null 2>&1; do sleep 0.2; done
[ -n "${clock}" ] && rosparam set /use_sim_time true
roslaunch -p "${port}" coral_introspection coral.launch \
  config:="${config}" input_type:=polar_image \
  polar_image:=/radar/polar fixed_frame:=odom output:=log >/dev/null 2>&1 &
pids+=($!)
rosbag play -q -l ${clock} -d 2 "${bag}" >/dev/null 2>&1 &
pids+=($!)
rosrun coral_introspection coral_stream_bench --monitor --alignment /alignment \
  --pid-of /coral_manager --duration "${duration}" --report 60 --warmup 10
