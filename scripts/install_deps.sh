#!/usr/bin/env bash
# Installs every Debian package the package needs to build, test and run its demo.
# Idempotent: packages already present are skipped by a cheap dpkg query, so a second run
# neither touches the network nor asks apt anything.
set -euo pipefail

PKGS=(
  # toolchain; clang-format 14 for scripts/ci/check_format.sh
  build-essential cmake pkg-config libgtest-dev libeigen3-dev clang-format-14
  ccache  # scripts/env.sh: a fresh clone reuses the objects of unchanged files
  # ROS 1 from Debian (Noetic-era, installs into /usr)
  ros-base-dev catkin ros-message-generation ros-message-runtime
  libroscpp-dev rosout rosbash python3-roslaunch python3-rostopic python3-rosservice python3-rosnode
  libnodeletlib-dev libnodelet-dev libnodeletlib-tools pluginlib-dev
  libtf2-dev libtf2-ros-dev libtf2-eigen-dev libtf2-msgs-dev python3-tf2-ros
  libsensor-msgs-dev libgeometry-msgs-dev libstd-msgs-dev libnav-msgs-dev libdiagnostic-msgs-dev
  python3-sensor-msgs python3-geometry-msgs python3-std-msgs python3-nav-msgs python3-diagnostic-msgs
  libpcl-conversions-dev libpcl-dev libopencv-dev
  # pcl_ros: its filter nodelets (libpcl_ros_filters.so) in front of CoralNodelet
  # (launch/coral_pcl_filters.launch); -dev pulls in every libpcl-ros-* library
  libpcl-ros-dev libpcl-ros-filters0d
  libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure
  libdiagnostic-updater-dev
  librosbag-dev python3-rosbag
  libyaml-cpp-dev  # coral_check reads presets
  librostest-dev python3-rostest python3-rosunit python3-rosparam
  python3-numpy
  # sanitizer build and libFuzzer harnesses (scripts/ci/test_sanitizers.sh, scripts/ci/fuzz.sh)
  clang libclang-rt-14-dev llvm-14
  # tools: CARMEN .clf.bz2 laser logs (eval)
  libbz2-dev
  # radar-inertial odometry (rio): Ceres solver
  libceres-dev
)

missing=()
for p in "${PKGS[@]}"; do
  # dpkg-query is local and fast; only what is not installed goes to apt.
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "[install_deps] all ${#PKGS[@]} packages already installed"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "[install_deps] installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
# apt-get update only when the package lists are absent or older than a day.
if [ -z "$(find /var/lib/apt/lists -maxdepth 1 -name '*Packages*' -mmin -1440 2>/dev/null | head -1)" ]; then
  $SUDO apt-get update -q
fi
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
