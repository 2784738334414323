#!/usr/bin/env bash
# ATE of cairn_slam on raw MIT CSAIL under small perturbations of the local SLAM, to tell a change's
# real effect from luck: MIT's single figure moves 0.07-0.17 m with any local-SLAM detail (the
# heading of its dead-end wing is set by a few weakly observed scans at one turn, tools/slam/README.md
# "Fifth pass"). Extra arguments go to every run, e.g.
#   tools/slam/ate_spread.sh --field-line-max-gap 0.6
# Prints each run's ATE and revisit consistency (reference_checks.h; the GMapping reference scores
# 3.14 cm), then their means and medians. Needs build/bin/cairn_slam{,_eval} and ../shared/data.
set -euo pipefail
cd "$(dirname "$0")/../.."
B=build/bin
D=${CAIRN_SHARED_DATA_DIR:-../shared/data}/carmen/mit-csail
for f in "$D/mit-csail.clf" "$D/csail.corrected.log"; do
  [ -f "$f" ] || { echo "ate_spread: data absent: $f" >&2; exit 2; }
done
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
perturbations=("" "--match-voxel 0.07" "--match-voxel 0.075" "--match-voxel 0.085" "--match-voxel 0.09"
               "--local-ceres-iterations 8" "--local-ceres-iterations 12"
               "--correlative-max-range-for-step 7" "--correlative-max-range-for-step 9")
ates=() revisits=()
for i in "${!perturbations[@]}"; do
  # shellcheck disable=SC2086  # the perturbation is a list of words
  "$B/cairn_slam" --log "$D/mit-csail.clf" --out "$out/$i" --no-map ${perturbations[$i]} "$@" >/dev/null
  "$B/cairn_slam_eval" --estimate "$out/$i/trajectory.csv" --reference "$D/csail.corrected.log" \
      --raw-log "$D/mit-csail.clf" --scan-checks >"$out/$i/eval.json"
  ate=$(sed -n 's/.*"ate_rmse_m": \([0-9.e-]*\).*/\1/p' "$out/$i/eval.json")
  # The estimate's revisit consistency (mean distance to the other pass): the first "mean_nn_m"
  # (nlohmann::json sorts keys: "estimate" before "reference").
  revisit=$(sed -n 's/.*"mean_nn_m": \([0-9.e-]*\).*/\1/p' "$out/$i/eval.json" | head -1)
  printf '%-36s ATE %.4f m, revisit consistency %.2f cm\n' "${perturbations[$i]:-(defaults)}" "$ate" \
      "$(awk -v v="$revisit" 'BEGIN {print v * 100}')"
  ates+=("$ate")
  revisits+=("$revisit")
done
stats() { sort -g | awk -v what="$1" -v unit="$2" -v k="$3" \
  '{v[NR]=$1 * k; s+=$1 * k} END {printf "%s: mean %.4f %s, median %.4f %s over %d runs\n", what, s/NR, unit, v[int((NR+1)/2)], unit, NR}'; }
printf '%s\n' "${ates[@]}" | stats ATE m 1
printf '%s\n' "${revisits[@]}" | stats "revisit consistency" cm 100
