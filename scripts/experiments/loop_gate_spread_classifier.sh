#!/usr/bin/env bash
# The lidar_2d classifier retrained on one log, judged by the loop verdict on the 2D loop
# candidates of both (doc/loop_closure.md): with aligned samples spread within the tolerance
# ("Tried and not kept", SPREAD=0.2 MIN_P=0.1, the defaults) or as the preset's was trained
# (SPREAD=0 MIN_P=preset: "The 2D classifier trained on the other log"). For each training log
# (ACES: the preset's own data, so ACES figures are in-sample for the classifier; Intel: ACES
# figures cross data set) it trains at SPREAD, writes a copy of config/lidar_2d.yaml with those
# betas and the loop gate's min_probability MIN_P ("preset": the preset's own; 0.1 was chosen
# on the even rows of the ACES point-to-point candidates: the smallest value with none of them
# false accepted), and prints the coral_loop_eval rows verdict / refined / classifier / oracle
# of the held-out odd rows, both registrations, both logs. With SWEEP=1 also the stream
# verdict's coral_error_sweep summary on every 4th relation of each log. About 5 min on 2
# cores (SWEEP=1: +3 min). Run from the repository root after building:
#   CORAL_WS=... bash scripts/experiments/loop_gate_spread_classifier.sh  (SPREAD=0.2 MIN_P=0.1 SWEEP=0)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
source scripts/env.sh
coral_source_ws
DATA="${CORAL_DATA_DIR:-../shared/data}"
SPREAD="${SPREAD:-0.2}"
MIN_P="${MIN_P:-0.1}"
SWEEP="${SWEEP:-0}"
OUT="$(mktemp -d /tmp/coral_spread.XXXXXX)"
declare -A LOG=([aces]="${DATA}/radish_aces/aces.clf.bz2" [intel]="${DATA}/radish_intel/intel.clf.bz2")
declare -A CORRECTED=([aces]="${DATA}/radish_intel/aces_corrected_poses_on_raw.csv"
  [intel]="${DATA}/radish_intel/intel_corrected_poses_on_raw.csv")
for train in aces intel; do
  rosrun coral_introspection coral_train --preset config/lidar_2d.yaml \
    --dataset "${train}=carmen:${LOG[${train}]}" --aligned_spread "${SPREAD}" --no_csv \
    --output "${OUT}/${train}" > "${OUT}/${train}.log" 2>&1 || { tail "${OUT}/${train}.log"; exit 1; }
  read -r b0 b1 b2 < <(awk '/^  beta[012]:/ {printf "%s ", $2} END {print ""}' "${OUT}/${train}/verdict.yaml")
  # The classifier's betas and, unless MIN_P=preset, the loop gate's min_probability (the first
  # "  min_probability:" line of the loop_closure section).
  sed -e "s/^  beta0: .*/  beta0: ${b0}/" -e "s/^  beta1: .*/  beta1: ${b1}/" \
    -e "s/^  beta2: .*/  beta2: ${b2}/" config/lidar_2d.yaml > "${OUT}/${train}.yaml"
  if [ "${MIN_P}" != preset ]; then
    sed -i -e "/^loop_closure:/,/^[a-z]/ s/^  min_probability: [0-9.e-]*/  min_probability: ${MIN_P}/" \
      "${OUT}/${train}.yaml"
    # A preset whose layout the pattern no longer matches must not run with its own value.
    awk '/^loop_closure:/ {in_loop = 1; next} /^[a-z]/ {in_loop = 0}
         in_loop && /^  min_probability:/ {print $2; exit}' "${OUT}/${train}.yaml" |
      grep -qx -- "${MIN_P}" || { echo "loop_closure/min_probability was not set to ${MIN_P}" >&2; exit 1; }
  fi
  echo "== classifier trained on ${train} (aligned_spread ${SPREAD}): beta ${b0} ${b1} ${b2}," \
    "loop min_probability ${MIN_P}"
  for test in aces intel; do
    for reg in icp point_to_line; do
      echo "-- ${test}, ${reg}, odd rows"
      rosrun coral_introspection coral_loop_eval --config "${OUT}/${train}.yaml" \
        --carmen "${LOG[${test}]}" --corrected "${CORRECTED[${test}]}" --registration "${reg}" \
        --rows odd 2> /dev/null | grep -E '^(gate|verdict|refined|classifier|oracle) '
    done
    if [ "${SWEEP}" = 1 ]; then
      echo "-- ${test}, stream verdict, every 4th relation (coral_error_sweep --stride 4)"
      rosrun coral_introspection coral_error_sweep --config "${OUT}/${train}.yaml" \
        --data "${test}=carmen:${LOG[${test}]}" --stride 4 2>&1 | grep -E 'right|accepted' || true
    fi
  done
done
rm -rf "${OUT}"
