#!/usr/bin/env bash
# File moves of issue 23 (layout), file by file so that it can run again after a merge: a file
# another branch added or kept at an old path is moved to the new one; nothing else happens.
#   runtime src/ + include/  |  evaluation toolbox toolbox/{src,include}
#   CoralNodelet-only ROS adapters: src/ros/<name> -> src/ros/coral_<name>
#   scripts by purpose: scripts/{ci,bench,experiments}/
# git mv only. Then: dev/layout_refs.py (paths), dev/namespaces.py (namespaces), clang-format.
set -euo pipefail
cd "$(git rev-parse --show-toplevel)"
mvv() {  # mvv OLD NEW: git mv when OLD is tracked and NEW does not exist
  [ -e "$1" ] || return 0
  if [ -e "$2" ]; then echo "both $1 and $2 exist: merge them by hand" >&2; return 0; fi
  mkdir -p "$(dirname "$2")"
  git mv "$1" "$2"
}
# 1. evaluation toolbox
for d in eval ros_eval tools; do
  [ -d src/$d ] && git ls-files src/$d | while read -r f; do mvv "$f" "toolbox/$f"; done
done
for d in eval ros_eval; do
  [ -d include/coral_introspection/$d ] && git ls-files include/coral_introspection/$d |
    while read -r f; do mvv "$f" "toolbox/$f"; done
done
# 2. CoralNodelet-only adapters
for f in check_alignment diagnostics outputs params scan_input scan_source tf_feed; do
  mvv src/ros/$f.cpp src/ros/coral_$f.cpp
  mvv include/coral_introspection/ros/$f.hpp include/coral_introspection/ros/coral_$f.hpp
done
# 3. scripts by purpose
for f in check_data.sh check_format.sh check_install.sh fuzz.sh mutation_check.sh test_sanitizers.sh; do
  mvv scripts/$f scripts/ci/$f
done
for f in stream_bench.sh soak_oxford.sh soak_rio.sh soak_rio_monitor.py; do
  mvv scripts/$f scripts/bench/$f
done
for f in aces_relation_icp.py relative_rule_sweep.py rio_demo_stats.py rio_loop_check.py rio_tables.py \
  verdict_report.sh rviz_screenshot.sh; do
  mvv scripts/$f scripts/experiments/$f
done
