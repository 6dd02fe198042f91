#!/usr/bin/env bash
# One-off file moves of issue 23 (layout): toolbox apart from the runtime, the two nodelets'
# adapters apart (prefix coral_ for CoralNodelet-only files), scripts sorted by purpose.
# git mv only; include paths and references are fixed by dev/layout_refs.py.
set -euo pipefail
cd "$(git rev-parse --show-toplevel)"
mvv() { mkdir -p "$(dirname "$2")"; git mv "$1" "$2"; }
# 1. evaluation toolbox
for d in eval ros_eval tools; do
  [ -d src/$d ] && mvv src/$d toolbox/src/$d
done
for d in eval ros_eval; do
  [ -d include/coral_introspection/$d ] && mvv include/coral_introspection/$d toolbox/include/coral_introspection/$d
done
# 2. CoralNodelet-only adapters
for f in check_alignment diagnostics outputs params scan_input scan_source tf_feed; do
  [ -e src/ros/$f.cpp ] && mvv src/ros/$f.cpp src/ros/coral_$f.cpp
  [ -e include/coral_introspection/ros/$f.hpp ] && mvv include/coral_introspection/ros/$f.hpp include/coral_introspection/ros/coral_$f.hpp
done
# 3. scripts by purpose
for f in check_data.sh check_format.sh check_install.sh fuzz.sh mutation_check.sh test_sanitizers.sh; do
  mvv scripts/$f scripts/ci/$f
done
for f in stream_bench.sh soak_oxford.sh soak_rio.sh soak_rio_monitor.py; do
  mvv scripts/$f scripts/bench/$f
done
for f in aces_relation_icp.py relative_rule_sweep.py rio_demo_stats.py rio_loop_check.py rio_tables.py verdict_report.sh rviz_screenshot.sh; do
  mvv scripts/$f scripts/experiments/$f
done
