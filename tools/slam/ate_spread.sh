#!/usr/bin/env bash
# ATE of cairn_slam on raw MIT CSAIL under small perturbations of the local SLAM, to tell a change's
# real effect from luck: MIT's single figure moves 0.07-0.17 m with any local-SLAM detail (the
# heading of its dead-end wing is set by a few weakly observed scans at one turn, tools/slam/README.md
# "Fifth pass"). Extra arguments go to every run, e.g.
#   tools/slam/ate_spread.sh --field-line-max-gap 0.6
# Prints each run's ATE, then the mean and median. Needs build/bin/cairn_slam{,_eval} and ../shared/data.
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
ates=()
for i in "${!perturbations[@]}"; do
  # shellcheck disable=SC2086  # the perturbation is a list of words
  "$B/cairn_slam" --log "$D/mit-csail.clf" --out "$out/$i" --no-map ${perturbations[$i]} "$@" >/dev/null
  ate=$("$B/cairn_slam_eval" --estimate "$out/$i/trajectory.csv" --reference "$D/csail.corrected.log" \
        --raw-log "$D/mit-csail.clf" | sed -n 's/.*"ate_rmse_m": \([0-9.e-]*\).*/\1/p')
  printf '%-36s ATE %.4f m\n' "${perturbations[$i]:-(defaults)}" "$ate"
  ates+=("$ate")
done
printf '%s\n' "${ates[@]}" | sort -g | awk '{v[NR]=$1; s+=$1} END {printf "mean %.4f m, median %.4f m over %d runs\n", s/NR, v[int((NR+1)/2)], NR}'
