#!/usr/bin/env bash
# Install-space check (run by scripts/test.sh after ctest; needs a built workspace):
#   1. `catkin_make install` of $CORAL_WS into $CORAL_WS/install (reuses the build folder);
#   2. the install space holds the plugin library, plugin XML, launch/config/rviz, the
#      executables, msg/srv files and their generated C++ headers and Python modules;
#   3. the installed nodelet plugin defines no symbol of the evaluation libraries (training,
#      logistic regression, NDT/CFEAR scores, reports, ROC, bag tooling);
#   4. in a clean environment with ONLY install/setup.bash sourced (no devel space),
#      `roslaunch coral_introspection coral.launch` on a free master port loads the nodelet
#      from the install space and its `check_alignment` service answers.
# Prints one line per check and a final "[check_install] PASS" or "[check_install] FAIL: ...";
# exit status 1 on any failure.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../env.sh"

INSTALL="${CORAL_WS}/install"
BUILD="${CORAL_WS}/build"
failures=()
ok() { echo "[check_install] ok: $*"; }
bad() {
  echo "[check_install] FAILED: $*"
  failures+=("$1")
}
finish() {
  if [ ${#failures[@]} -eq 0 ]; then
    echo "[check_install] PASS: install space loads the nodelet, check_alignment answers, no eval code in the plugin"
    exit 0
  fi
  echo "[check_install] FAIL: ${failures[*]}"
  exit 1
}

# 1. Install (the same cache and flags as coral_build, so nothing is recompiled).
echo "[check_install] catkin_make install into ${INSTALL}"
# shellcheck disable=SC2046
if ! (cd "${CORAL_WS}" && catkin_make $(coral_launcher_args) -DCMAKE_BUILD_TYPE=Release \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 -j"$(nproc)" install >"${CORAL_WS}/install.log" 2>&1); then
  tail -30 "${CORAL_WS}/install.log"
  bad "catkin_make_install"
  finish
fi
ok "catkin_make install (log: ${CORAL_WS}/install.log)"

# 2. Files the nodelet, the launch files and message users need.
PY_SITE="$(cd "${INSTALL}" && ls -d lib/python3*/dist-packages 2>/dev/null | head -1)"
for f in lib/libcoral_introspection_nodelets.so share/coral_introspection/nodelet_plugins.xml \
  share/coral_introspection/package.xml share/coral_introspection/launch/coral.launch \
  share/coral_introspection/launch/demo.launch share/coral_introspection/rviz/coral.rviz \
  share/coral_introspection/config/lidar_3d.yaml share/coral_introspection/config/radar_oxford.yaml \
  share/coral_introspection/msg/AlignmentQuality.msg \
  share/coral_introspection/msg/VelocityConsistency.msg \
  share/coral_introspection/srv/CheckAlignment.srv include/coral_introspection/AlignmentQuality.h \
  include/coral_introspection/CheckAlignment.h include/coral_introspection/CoralConfig.h \
  include/coral_introspection/coral/coral.hpp lib/coral_introspection/coral_node \
  lib/coral_introspection/coral_sequence_demo lib/coral_introspection/coral_train \
  "${PY_SITE}/coral_introspection/msg/_AlignmentQuality.py" \
  "${PY_SITE}/coral_introspection/srv/_CheckAlignment.py"; do
  [ -e "${INSTALL}/${f}" ] || bad "missing_${f##*/}"
done
[ ${#failures[@]} -eq 0 ] && ok "plugin, plugin XML, launch, config, rviz, executables, msg/srv (+ C++/Python) installed"

# 3. No evaluation code in the installed plugin: no strong (T) symbol of the eval or
# ros_eval libraries is defined in it, and no name of the training/baseline/report code.
PLUGIN="${INSTALL}/lib/libcoral_introspection_nodelets.so"
EVAL_SYMS="$(mktemp)" PLUGIN_SYMS="$(mktemp)"
trap 'rm -f "${EVAL_SYMS}" "${PLUGIN_SYMS}"' EXIT
eval_libs=()
for lib in coral_introspection_eval coral_introspection_ros_eval; do
  found="$(find "${CORAL_WS}/devel/lib" "${BUILD}" -name "lib${lib}.a" 2>/dev/null | head -1)"
  if [ -z "${found}" ]; then bad "lib${lib}.a_not_found"; else eval_libs+=("${found}"); fi
done
if [ -f "${PLUGIN}" ] && [ ${#eval_libs[@]} -eq 2 ]; then
  nm -C --defined-only "${eval_libs[@]}" 2>/dev/null | awk '$2 == "T" { $1 = ""; $2 = ""; print }' |
    sed 's/^  //' | sort -u >"${EVAL_SYMS}"
  nm -C -D --defined-only "${PLUGIN}" | awk '{ $1 = ""; $2 = ""; print }' | sed 's/^  //' |
    sort -u >"${PLUGIN_SYMS}"
  nm -C --defined-only "${PLUGIN}" 2>/dev/null | awk '{ $1 = ""; $2 = ""; print }' |
    sed 's/^  //' | sort -u >>"${PLUGIN_SYMS}"
  shared="$(sort -u "${PLUGIN_SYMS}" | comm -12 - "${EVAL_SYMS}")"
  named="$(grep -E 'coral_introspection::(coral|radar|eval|ros_adapters|ros_eval)::[A-Za-z_:]*([Nn]dt|[Cc]fear|Roc|roc[A-Z]|[Rr]eport|[Tt]raining|Evaluation|evaluate|OxfordDataset|crossValid)' \
    "${PLUGIN_SYMS}" | grep -v -e 'ros_adapters::reportStatus(' -e 'coral::rocCurve(' -e 'coral::RocPoint' \
      -e 'coral::CoralPair::' || true)"
  # (reportStatus: the AlignmentQuality status of an online::Report, the nodelet's own code.
  # The logistic-regression fit and the metrics (auc, rocCurve in the same object file) are
  # coral code since online self-calibration refits the classifier in the nodelet.
  # CoralPair::evaluate is CorAl at a pose, the verdict's own computation.)
  if [ "$(wc -l <"${EVAL_SYMS}")" -lt 20 ]; then
    bad "eval_symbol_list_too_short"  # the comparison would prove nothing
  elif [ -n "${shared}${named}" ]; then
    echo "${shared}${named}" | head -20
    bad "eval_code_in_plugin"
  else
    ok "plugin defines none of the $(wc -l <"${EVAL_SYMS}") eval/ros_eval functions and no training/NDT/CFEAR/report/ROC name"
  fi
fi

# 4. Launch from the install space alone, in an environment without the devel space.
PORT="$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("", 0)); print(s.getsockname()[1])')"
CLIENT="$(mktemp /tmp/coral_install_client.XXXXXX.py)"
LOG="$(mktemp /tmp/coral_install_launch.XXXXXX.log)"
trap 'rm -f "${EVAL_SYMS}" "${PLUGIN_SYMS}" "${CLIENT}"' EXIT
cat >"${CLIENT}" <<'EOF'
# Calls check_alignment with two small clouds: the same wall corner twice (identity
# transform) must be judged valid and aligned with every point counted.
import math, struct, sys, time
import rosgraph, rospy, rospkg
from sensor_msgs.msg import PointCloud2, PointField
from coral_introspection.srv import CheckAlignment, CheckAlignmentRequest

pkg = rospkg.RosPack().get_path("coral_introspection")
print("[check_install] rospack find coral_introspection:", pkg)
if not pkg.startswith(sys.argv[1]):
    sys.exit("package found outside the install space: " + pkg)

pts = []
for i in range(40):            # two walls and a floor, 0.1 m grid (corner of a room)
    for j in range(20):
        a, b = 0.1 * i, 0.1 * j
        pts += [(a, 0.0, b), (0.0, a + 0.1, b), (a + 0.05, 0.1 * j + 0.1, 0.0)]
cloud = PointCloud2()
cloud.header.frame_id = "lidar"
cloud.height, cloud.width = 1, len(pts)
cloud.fields = [PointField(n, 4 * k, PointField.FLOAT32, 1) for k, n in enumerate("xyz")]
cloud.point_step, cloud.row_step = 12, 12 * len(pts)
cloud.data = b"".join(struct.pack("<fff", *p) for p in pts)
req = CheckAlignmentRequest(cloud_a=cloud, cloud_b=cloud)
req.transform_a_b.rotation.w = 1.0
deadline = time.time() + 60
while not rosgraph.is_master_online() and time.time() < deadline:  # roslaunch starts it
    time.sleep(0.2)
rospy.wait_for_service("check_alignment", timeout=max(1.0, deadline - time.time()))
res = rospy.ServiceProxy("check_alignment", CheckAlignment)(req).result
print("[check_install] check_alignment: valid=%s aligned=%s p=%.3f Q=%.4f points=%d/%d" %
      (res.valid, res.aligned, res.probability, res.quality, res.num_points_a, res.num_points_b))
ok = res.valid and res.aligned and res.num_points_a == len(pts) and math.isfinite(res.quality)
sys.exit(0 if ok else "unexpected answer")
EOF

# env -i: nothing of the calling shell (no devel space, no ROS_PACKAGE_PATH) leaks in.
if env -i HOME="${HOME}" PATH="/usr/bin:/bin" ROS_HOME="$(mktemp -d /tmp/coral_install_home.XXXXXX)" \
  INSTALL="${INSTALL}" PORT="${PORT}" CLIENT="${CLIENT}" LOG="${LOG}" \
  bash -c '
    source "${INSTALL}/setup.bash"
    export ROS_MASTER_URI="http://localhost:${PORT}"
    case ":${CMAKE_PREFIX_PATH:-}:${ROS_PACKAGE_PATH:-}:" in
      *devel*) echo "[check_install] devel space in the environment: ${CMAKE_PREFIX_PATH}"; exit 1 ;;
    esac
    roslaunch -p "${PORT}" coral_introspection coral.launch >"${LOG}" 2>&1 &
    launch=$!
    /usr/bin/timeout 90 /usr/bin/python3 "${CLIENT}" "${INSTALL}"
    rc=$?
    # The manager must have mapped the plugin from the install space.
    manager="$(pgrep -P "${launch}" -f "nodelet manager" | head -1 || true)"
    if [ -n "${manager}" ]; then
      grep -o "/[^ ]*libcoral_introspection_nodelets.so" "/proc/${manager}/maps" | sort -u |
        sed "s/^/[check_install] manager mapped: /"
      grep -q "${INSTALL}/lib/libcoral_introspection_nodelets.so" "/proc/${manager}/maps" || rc=1
    else
      echo "[check_install] nodelet manager process not found"; rc=1
    fi
    # SIGTERM: a background job of a non-interactive shell ignores SIGINT.
    kill -TERM "${launch}" 2>/dev/null; wait "${launch}" 2>/dev/null
    exit "${rc}"
  '; then
  ok "roslaunch coral_introspection coral.launch from the install space alone; check_alignment answered"
else
  echo "--- roslaunch log (last 30 lines)"
  tail -30 "${LOG}"
  bad "launch_from_install_space"
fi
rm -f "${LOG}"
finish
