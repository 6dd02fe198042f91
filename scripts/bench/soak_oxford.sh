#!/usr/bin/env bash
# Soak: the Oxford radar scans (../shared/data/oxford_radar_tiny) as a rosbag played in a
# loop (`rosbag play -l`, with --clock if asked) through CoralNodelet for a given time;
# coral_stream_bench --monitor prints memory, verdict rate, latency and how many loops were
# judged after their first scan.
#   scripts/bench/soak_oxford.sh [--port 11311] [--duration 1800] [--clock] [--data DIR] [--config FILE]
# (--config: parameter file of the nodelet, default config/radar_oxford.yaml)
# Expects a built workspace (coral_build). Everything it starts is stopped on exit.
set -euo pipefail
# shellcheck source-path=SCRIPTDIR source=../ros_session.sh
source "$(dirname "${BASH_SOURCE[0]}")/../ros_session.sh"
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
session_tmp="$(mktemp -d)"
bag="${session_tmp}/oxford.bag"
rosrun coral_introspection oxford_to_bag "${data}" "${bag}"
session_roscore "${port}"
[ -n "${clock}" ] && rosparam set /use_sim_time true
session_bg roslaunch -p "${port}" coral_introspection coral.launch \
  config:="${config}" input_type:=polar_image \
  polar_image:=/radar/polar fixed_frame:=odom output:=log
# shellcheck disable=SC2086  # ${clock}: empty or --clock
session_bg rosbag play -q -l ${clock} -d 2 "${bag}"
rosrun coral_introspection coral_stream_bench --monitor --alignment /alignment \
  --pid-of /coral_manager --duration "${duration}" --report 60 --warmup 10
