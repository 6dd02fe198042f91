#!/usr/bin/env bash
# Installs what is needed, builds the package and runs the demo:
#   1. CorAl on a built-in synthetic pair (aligned, then with induced offsets): verdicts;
#   2. a simulated drive replayed through the nodelet with injected odometry errors
#      (roslaunch coral_introspection demo.launch): how many were flagged.
# Idempotent: installed packages and built objects are reused.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
bash "${CORAL_REPO}/scripts/install_deps.sh"
coral_build
echo "=== CorAl on the built-in synthetic pair"
rosrun coral_introspection coral_demo_pair
if [ -f "${CORAL_REPO}/launch/demo.launch" ]; then
  echo "=== Simulated drive through the nodelet with injected odometry errors"
  roslaunch coral_introspection demo.launch "$@"
fi
