#!/usr/bin/env bash
# The lidar_2d classifier retrained with aligned samples spread within the tolerance
# (coral_train --aligned_spread), judged by the loop verdict on the 2D loop candidates
# (doc/loop_closure.md, "Tried and not kept"). For each training log (ACES: the preset's own
# data, so ACES figures are in-sample for the classifier; Intel: ACES figures cross data set)
# it trains at SPREAD, writes a copy of config/lidar_2d.yaml with those betas and the loop
# gate's min_probability MIN_P (chosen on the even rows of the ACES point-to-point candidates:
# the smallest value with none of them false accepted), and prints the coral_loop_eval rows
# verdict / refined / classifier / oracle of the held-out odd rows, both registrations, both
# logs. About 5 min on 2 cores. Run from the repository root after building:
#   CORAL_WS=... bash scripts/experiments/loop_gate_spread_classifier.sh  (SPREAD=0.2 MIN_P=0.1)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
source scripts/env.sh
coral_source_ws
DATA="${CORAL_DATA_DIR:-../shared/data}"
SPREAD="${SPREAD:-0.2}"
MIN_P="${MIN_P:-0.1}"
OUT="$(mktemp -d /tmp/coral_spread.XXXXXX)"
declare -A LOG=([aces]="${DATA}/radish_aces/aces.clf.bz2" [intel]="${DATA}/radish_intel/intel.clf.bz2")
declare -A CORRECTED=([aces]="${DATA}/radish_intel/aces_corrected_poses_on_raw.csv"
  [intel]="${DATA}/radish_intel/intel_corrected_poses_on_raw.csv")
for train in aces intel; do
  rosrun coral_introspection coral_train --preset config/lidar_2d.yaml \
    --dataset "${train}=carmen:${LOG[${train}]}" --aligned_spread "${SPREAD}" --no_csv \
    --output "${OUT}/${train}" > "${OUT}/${train}.log" 2>&1 || { tail "${OUT}/${train}.log"; exit 1; }
  read -r b0 b1 b2 < <(awk '/^  beta[012]:/ {printf "%s ", $2} END {print ""}' "${OUT}/${train}/verdict.yaml")
  # The classifier's betas and the loop gate's min_probability (the only line of the
  # loop_closure section starting "  min_probability: 0.01").
  sed -e "s/^  beta0: .*/  beta0: ${b0}/" -e "s/^  beta1: .*/  beta1: ${b1}/" \
    -e "s/^  beta2: .*/  beta2: ${b2}/" \
    -e "/^loop_closure:/,/^[a-z]/ s/^  min_probability: 0.01 .*/  min_probability: ${MIN_P}/" \
    config/lidar_2d.yaml > "${OUT}/${train}.yaml"
  echo "== classifier trained on ${train} (aligned_spread ${SPREAD}): beta ${b0} ${b1} ${b2}," \
    "loop min_probability ${MIN_P}"
  for test in aces intel; do
    for reg in icp point_to_line; do
      echo "-- ${test}, ${reg}, odd rows"
      rosrun coral_introspection coral_loop_eval --config "${OUT}/${train}.yaml" \
        --carmen "${LOG[${test}]}" --corrected "${CORRECTED[${test}]}" --registration "${reg}" \
        --rows odd 2> /dev/null | grep -E '^(gate|verdict|refined|classifier|oracle) '
    done
  done
done
rm -rf "${OUT}"
