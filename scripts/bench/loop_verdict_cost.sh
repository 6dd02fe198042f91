#!/usr/bin/env bash
# The cost of a loop-closure verdict on the 64-beam pair of doc/benchmarks_lidar.md by what the
# candidate is: the pair's own pose (accepted: the restart check runs) and the same pose moved
# by 0.2, 0.6, 1.2 m along x, 3 m along y, 10 m along x and turned by 15, 90, 180 deg
# (rejected at the pose: registered once from it, loop_closure/max_registered_offset). Prints
# one row per candidate: the verdict, the term that rejected it and the median `seconds` of
# `coral_check --loop_closure --repeat REPEAT` on one core (taskset -c 1 when present), for
# each run of RUNS. doc/loop_closure.md "The cost of a rejection". Expects a built workspace.
# With --stream the same candidates, and the pose turned by 0.5 and 1 deg, are judged by the
# stream verdict instead (coral_check without --loop_closure): a 64-beam odometry pair, what its
# gate's coarse probe costs where the classifier is unsure (doc/verdict_every_error.md "Speed").
#   bash scripts/bench/loop_verdict_cost.sh [--config config/lidar_3d.yaml] [--repeat 21] [--runs 2]
#       [--stream]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
# shellcheck source=../env.sh disable=SC1091
source scripts/env.sh
coral_source_ws
config=config/lidar_3d.yaml
repeat=21
runs=2
loop=(--loop_closure)
names="pose x+0.2m x+0.6m x+1.2m y+3m x+10m yaw15 yaw90 yaw180"
while [ $# -gt 0 ]; do
  case "$1" in
    --stream) loop=(); names="pose yaw0.5 yaw1 ${names#pose }"; shift ;;
    --config) config="$2"; shift 2 ;;
    --repeat) repeat="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    *) echo "unknown argument $1 (--config FILE, --repeat N, --runs N, --stream)" >&2; exit 2 ;;
  esac
done
[ -f "${config}" ] || { echo "no preset ${config}" >&2; exit 2; }
[[ "${repeat}" =~ ^[1-9][0-9]*$ && "${runs}" =~ ^[1-9][0-9]*$ ]] ||
  { echo "--repeat and --runs take a positive integer" >&2; exit 2; }
dir="$(mktemp -d /tmp/coral_loop_cost.XXXXXX)"
trap 'rm -rf "${dir}"' EXIT
rosrun coral_introspection coral_benchmark_lidar --write_pair "${dir}" >/dev/null
# The candidates: T_a_b * delta (delta: x, y [m], yaw [deg] in b's frame).
/usr/bin/python3 - "${dir}" <<'EOF'
import sys
import numpy as np
d = sys.argv[1]
T = np.loadtxt(d + "/T_a_b.txt").reshape(-1, 4)
if T.shape[0] == 3:
    T = np.vstack([T, [0, 0, 0, 1]])
for name, x, y, yaw in [("pose", 0, 0, 0), ("x+0.2m", 0.2, 0, 0), ("x+0.6m", 0.6, 0, 0),
                        ("x+1.2m", 1.2, 0, 0), ("y+3m", 0, 3, 0), ("x+10m", 10, 0, 0),
                        ("yaw15", 0, 0, 15), ("yaw90", 0, 0, 90), ("yaw180", 0, 0, 180),
                        ("yaw0.5", 0, 0, 0.5), ("yaw1", 0, 0, 1)]:
    c, s = np.cos(np.radians(yaw)), np.sin(np.radians(yaw))
    D = np.eye(4)
    D[:2, :2] = [[c, -s], [s, c]]
    D[0, 3], D[1, 3] = x, y
    np.savetxt("%s/cand_%s.txt" % (d, name), T @ D)
EOF
pin=()
if command -v taskset >/dev/null; then pin=(taskset -c 1); fi
printf '%-8s %-8s %-44s %s\n' candidate aligned rejected_by "seconds (median per run)"
for name in ${names}; do
  times=""
  for _ in $(seq "${runs}"); do
    line="$("${pin[@]}" rosrun coral_introspection coral_check --config "${config}" "${loop[@]}" \
      --a "${dir}/a.bin" --b "${dir}/b.bin" --transform_file "${dir}/cand_${name}.txt" \
      --repeat "${repeat}")"
    times+="$(echo "${line}" |
      /usr/bin/python3 -c 'import json,sys; print("%.3f" % json.load(sys.stdin)["seconds"])') "
  done
  echo "${line}" | /usr/bin/python3 -c '
import json, sys
j = json.load(sys.stdin)
print("%-8s %-8s %-44s %s" % (sys.argv[1], j["aligned"], j["rejected_by"][:44], sys.argv[2]))' \
    "${name}" "${times}"
done
