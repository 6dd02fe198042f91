#!/usr/bin/env bash
# Renders the demo in rviz under a virtual X server and saves a screenshot of the quality
# cloud while a misaligned pair (an injected odometry error) is displayed:
#   scripts/experiments/rviz_screenshot.sh [output.png]        (default: doc/rviz_quality_cloud.png)
# Extra demo.launch args via $CORAL_DEMO_ARGS, e.g. CORAL_DEMO_ARGS="mode:=oxford".
# Needs a built workspace (source its devel/setup.bash first, or set CORAL_WS to it).
# Installs rviz, xvfb and imagemagick from Debian when missing (idempotent dpkg check).
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
OUT="${1:-$HERE/doc/rviz_quality_cloud.png}"
DISP="${CORAL_DISPLAY:-:99}"
HOLD=25        # [s] the demo pauses this long on the first flagged injected pair
export PATH=/usr/bin:$PATH   # ROS python tools need the system python

# 1. Dependencies (rviz needs no other package of ours).
missing=()
for p in rviz xvfb imagemagick; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  echo "[rviz_screenshot] installing ${missing[*]}"
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

if [ -n "${CORAL_WS:-}" ]; then
  set +u; source "$CORAL_WS/devel/setup.bash"; set -u
fi
rospack find coral_introspection >/dev/null || {
  echo "[rviz_screenshot] coral_introspection not found: source your workspace's devel/setup.bash" >&2
  exit 1
}

LOG="$(mktemp /tmp/coral_rviz_demo.XXXXXX.log)"
XVFB_PID="" ; LAUNCH_PID=""
cleanup() {
  [ -n "$LAUNCH_PID" ] && kill -INT "$LAUNCH_PID" 2>/dev/null && wait "$LAUNCH_PID" 2>/dev/null || true
  [ -n "$XVFB_PID" ] && kill "$XVFB_PID" 2>/dev/null || true
  rm -f "$LOG"
}
trap cleanup EXIT

# 2. Virtual display, software OpenGL.
Xvfb "$DISP" -screen 0 1280x800x24 -nolisten tcp >/dev/null 2>&1 &
XVFB_PID=$!
sleep 2
export DISPLAY="$DISP" LIBGL_ALWAYS_SOFTWARE=1

# 3. Demo with rviz; it holds the first detected injected error on screen for $HOLD s.
# A private ROS master port so a running roscore is not disturbed.
export ROS_MASTER_URI="http://localhost:${CORAL_MASTER_PORT:-11399}"
roslaunch -p "${CORAL_MASTER_PORT:-11399}" coral_introspection demo.launch rviz:=true \
  hold_misaligned:=$HOLD start_delay:=8 ${CORAL_DEMO_ARGS:-} >"$LOG" 2>&1 &
LAUNCH_PID=$!

for _ in $(seq 1 150); do
  grep -q "HOLD misaligned pair" "$LOG" && break
  kill -0 "$LAUNCH_PID" 2>/dev/null || break
  sleep 1
done
if ! grep -q "HOLD misaligned pair" "$LOG"; then
  echo "[rviz_screenshot] the demo never showed a flagged injected pair; log:" >&2
  tail -40 "$LOG" >&2
  exit 1
fi
grep "HOLD misaligned pair" "$LOG"
sleep 6   # let rviz receive and render the quality cloud of that pair

mkdir -p "$(dirname "$OUT")"
# Quantised PNG keeps the file small (< 500 KB) for the README.
import -window root +dither -colors 64 "$OUT"
echo "[rviz_screenshot] wrote $OUT ($(du -k "$OUT" | cut -f1) KB)"
