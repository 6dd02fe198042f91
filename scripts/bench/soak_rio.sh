#!/usr/bin/env bash
# Soak: the TI mmWave radar + IMU bag (../shared/data/ti_mmwave_demo, 40.3 s) played in a loop
# (`rosbag play -l`) through RioNodelet (launch/rio.launch, own manager /rio_manager) for a given
# time; scripts/bench/soak_rio_monitor.py samples the manager's RSS, counts the odometry per loop and
# reads the nodelet's diagnostics, prints a summary and fails (exit 1) when the RSS grew by more
# than --max-growth percent from the steady state (after 2 loops), the odometry stopped, or the
# manager crashed.
#   scripts/bench/soak_rio.sh [--port 11311] [--duration 1800] [--data DIR] [--config FILE]
#       [--heap-release-interval S] [--interval S] [--max-growth PERCENT] [--keep-going]
# (--keep-going: measure the whole duration even after the odometry stopped; still exit 1)
# No --clock: RioNodelet times everything by the message stamps (trigger, IMU), which jump back
# 40 s at each loop; the estimator restarts on that ("time jumps back"), the trigger matching on
# the sequence numbers starting over ("trigger sequence restarts"); nothing else in the manager
# reads ROS time. Expects a built workspace (coral_build). Everything it starts is stopped on
# exit.
set -euo pipefail
# shellcheck source-path=SCRIPTDIR source=../ros_session.sh
source "$(dirname "${BASH_SOURCE[0]}")/../ros_session.sh"
port=11311
duration=1800
config="${CORAL_REPO}/config/rio_ti_mmwave.yaml"
data="${CORAL_DATA_DIR:-${CORAL_REPO}/../shared/data}/ti_mmwave_demo"
heap_release_interval=10.0
monitor=()
while [ $# -gt 0 ]; do
  case "$1" in
    --port) port="$2"; shift 2 ;;
    --duration) duration="$2"; shift 2 ;;
    --data) data="$2"; shift 2 ;;
    --config) config="$2"; shift 2 ;;
    --heap-release-interval) heap_release_interval="$2"; shift 2 ;;
    --interval | --max-growth | --steady-loops | --report | --stall) monitor+=("$1" "$2"); shift 2 ;;
    --keep-going) monitor+=("$1"); shift ;;
    *) echo "unknown argument $1" >&2; exit 2 ;;
  esac
done
bag="${data}/ti_mmwave_rospkg_demo.bag"
[ -f "${bag}" ] || { echo "no TI bag at ${bag} (--data)" >&2; exit 2; }
session_tmp="$(mktemp -d)"
session_roscore "${port}"
session_bg roslaunch -p "${port}" coral_introspection rio.launch config:="${config}" \
  radar:=/ti_mmwave/radar_scan_pcl imu:=/sensor_platform/imu \
  trigger:=/sensor_platform/radar_right/trigger baro:=/sensor_platform/baro \
  heap_release_interval:="${heap_release_interval}" output:=log
# The monitor subscribes before the bag starts, so that the first loop is counted whole.
"$(dirname "${BASH_SOURCE[0]}")/soak_rio_monitor.py" --pid-of /rio_manager \
  --duration "${duration}" --ready "${session_tmp}/ready" "${monitor[@]}" &
monitor_pid=$!
session_pids+=("${monitor_pid}")
until [ -s "${session_tmp}/ready" ]; do
  kill -0 "${monitor_pid}" 2>/dev/null || break
  sleep 0.5
done
session_bg rosbag play -q -l -d 2 "${bag}"
rc=0
wait "${monitor_pid}" || rc=$?
exit "${rc}"
