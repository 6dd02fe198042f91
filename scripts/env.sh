# Sourced by the project's scripts: the system python first (pyenv's lacks catkin_pkg and
# the ROS modules), the catkin workspace outside the source tree, ROS logs out of $HOME.
CORAL_REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
export CORAL_WS="${CORAL_WS:-${HOME}/.cache/coral_introspection/ws}"
export ROS_HOME="${ROS_HOME:-${CORAL_WS}/ros_home}"
export PYTHONNOUSERSITE=1
unset PYTHONPATH PYTHONHOME
# Compiler cache (ccache, scripts/install_deps.sh). A fresh clone (CI) gives every file a new
# mtime, so make would compile everything again; ccache hashes the preprocessed source and
# hands back the objects of unchanged files. Every build of these scripts (workspace,
# sanitizer and mutation builds) passes coral_launcher_args; the cache lives beside them.
export CCACHE_DIR="${CCACHE_DIR:-${HOME}/.cache/coral_introspection/ccache}"
export CCACHE_MAXSIZE="${CCACHE_MAXSIZE:-12G}"
coral_launcher_args() {
  if command -v ccache > /dev/null; then
    echo "-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache"
  fi
}

# Links this source tree into the catkin workspace $1 and prints --force-cmake when the
# workspace was last configured for another tree (another clone): the test binaries carry the
# source path that CMake resolved (CORAL_SOURCE_DIR), and catkin_make does not re-run CMake for
# a moved link, so without it the tests would read the other clone's configs. The resolved path
# of the last configure is kept in build/coral_source_configured, so a link set back by hand
# (ln -sfn) is caught too.
coral_link_source() {
  local link="$1/src/coral_introspection" real
  real="$(cd "${CORAL_REPO}" && pwd -P)"
  mkdir -p "$1/src"
  [ "$(readlink "${link}" 2>/dev/null)" = "${CORAL_REPO}" ] || ln -sfn "${CORAL_REPO}" "${link}"
  [ -f "$1/build/CMakeCache.txt" ] || return 0
  local configured="$1/build/coral_source_configured"
  local stamp="$1/build/coral_messages_configured.stamp"
  if [ "$(cat "${configured}" 2>/dev/null)" != "${real}" ]; then
    echo "${real}" >"${configured}"
    touch "${stamp}"
    echo "--force-cmake"
  # A message or service changed since the last configure (a pull that adds a field): genmsg's
  # dependency check stops make with "Please rerun cmake" instead of regenerating. The stamp
  # marks the configure that saw them (CMakeCache.txt keeps its time when nothing in it changes).
  else
    [ -f "${stamp}" ] || touch -r "$1/build/CMakeCache.txt" "${stamp}"
    if [ -n "$(find "${CORAL_REPO}/msg" "${CORAL_REPO}/srv" -newer "${stamp}" -print -quit \
      2>/dev/null)" ]; then
      touch "${stamp}"
      echo "--force-cmake"
    fi
  fi
  return 0
}

# Builds (incrementally) the package and, with argument "tests", its test targets; with
# argument "demo" only what scripts/demo.sh runs (the nodelet plugin, the two demo programs
# and the messages), not every tool.
coral_build() {
  mkdir -p "${ROS_HOME}"
  local jobs force launcher
  force="$(coral_link_source "${CORAL_WS}")"
  launcher="$(coral_launcher_args)"
  jobs="$(nproc)"
  # Every step exits on failure by itself: the caller's `set -e` does not reach into a
  # subshell whose status is tested, and an interactive caller has none.
  (
    cd "${CORAL_WS}" || exit 1
    # shellcheck disable=SC2086  # ${force}, ${launcher}: words or empty
    if [ "${1:-}" = "demo" ]; then
      catkin_make ${force} ${launcher} -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 \
        -j"${jobs}" coral_introspection_generate_messages coral_introspection_nodelets coral_demo_pair \
        coral_sequence_demo || exit $?
    else
      catkin_make ${force} ${launcher} -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 \
        -j"${jobs}" || exit $?
    fi
    if [ "${1:-}" = "tests" ]; then
      # shellcheck disable=SC2086
      catkin_make ${launcher} -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 \
        -j"${jobs}" tests || exit $?
    fi
  ) || return $?
  coral_source_ws
}

# Sources the built workspace ${CORAL_WS}: setup.bash reads unset variables, so -u is relaxed
# while it runs (and set again after).
coral_source_ws() {
  set +u
  # shellcheck disable=SC1091
  source "${CORAL_WS}/devel/setup.bash"
  set -u
}
