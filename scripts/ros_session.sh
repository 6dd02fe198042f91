# shellcheck shell=bash source-path=SCRIPTDIR
# Sourced by the scripts that start their own ROS master from the built workspace
# (bench/stream_bench.sh, bench/soak_oxford.sh, bench/soak_rio.sh): the built workspace, an own
# ROS master, background processes that are stopped (and a temporary directory that is
# removed) when the sourcing script exits. Not used by demo.sh (roslaunch in the foreground,
# stopped with SIGINT once the demo wrote its result), ci/check_install.sh (the install space
# alone, no devel space) and experiments/rviz_screenshot.sh (SIGINT to roslaunch, Xvfb).
#   source "$(dirname "${BASH_SOURCE[0]}")/ros_session.sh"
#   session_roscore PORT          # master on PORT (refused if one answers there already)
#   session_bg CMD ARGS...        # CMD in the background, output discarded, stopped on exit
#   session_tmp="$(mktemp -d)"    # removed on exit
# shellcheck source=env.sh disable=SC1091
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
coral_source_ws

session_pids=()
session_tmp=""
session_cleanup() {
  local p
  for p in "${session_pids[@]}"; do kill "${p}" 2>/dev/null || true; done
  wait 2>/dev/null || true
  if [ -n "${session_tmp}" ]; then rm -rf "${session_tmp}"; fi
}
trap session_cleanup EXIT

session_bg() {
  "$@" >/dev/null 2>&1 &
  session_pids+=($!)
}

session_roscore() {
  export ROS_MASTER_URI="http://localhost:$1"
  if rosparam list >/dev/null 2>&1; then
    echo "a ROS master already answers on port $1: choose another (--port)" >&2
    exit 2
  fi
  session_bg roscore -p "$1"
  until rosparam list >/dev/null 2>&1; do sleep 0.2; done
}
