#!/usr/bin/env bash
# ATE of cairn_slam against the simulator's exact truth, over every robot of worlds/office.yaml (3)
# and worlds/collapsed.yaml (4) and three simulator seeds (7, 8, 9): 21 runs per sensor set, ~25 s.
# The CARMEN references are GMapping output, ~5 cm accurate; this error is ours alone.
# Sensor sets (the odometry's noise is the simulator's random walk per sqrt(metre), sim_options.h):
#   world   the worlds' own: 360 deg, 360 beams, 12 m, 1 cm noise; odometry 5 %, 0.02 rad per metre
#   carmen  a SICK-like laser as in the CARMEN logs: 180 deg, 181 beams (1 deg), 30 m, 2 cm noise;
#           odometry 10 %, 3 deg per metre (the issue's noise level)
#   carmen05  the same with 361 beams (0.5 deg, as raw MIT)
# Extra arguments go to every cairn_slam run, e.g. `tools/slam/sim_truth.sh carmen --no-loop-closure`.
# Prints each set's mean, median and worst ATE. Needs build/bin/cairn_{slam,slam_eval,mrlog}.
set -euo pipefail
cd "$(dirname "$0")/../.."
B=$PWD/build/bin
sets=${1:-world carmen carmen05}
shift || true
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
laser_of() {
  case $1 in
    world) echo "rate_hz: 10, beams: 360, fov_deg: 360, max_range_m: 12, noise_sd_m: 0.01" ;;
    carmen) echo "rate_hz: 10, beams: 181, fov_deg: 180, max_range_m: 30, noise_sd_m: 0.02" ;;
    carmen05) echo "rate_hz: 10, beams: 361, fov_deg: 180, max_range_m: 30, noise_sd_m: 0.02" ;;
    *) echo "sim_truth: unknown sensor set '$1' (world, carmen, carmen05)" >&2; exit 2 ;;
  esac
}
odometry_of() {
  case $1 in
    world) echo "rate_hz: 20, trans_noise_per_m: 0.05, rot_noise_rad_per_m: 0.02, rot_noise_per_rad: 0.05" ;;
    *) echo "rate_hz: 20, trans_noise_per_m: 0.10, rot_noise_rad_per_m: 0.05236, rot_noise_per_rad: 0.05" ;;
  esac
}
for set in $sets; do
  laser=$(laser_of "$set")
  odometry=$(odometry_of "$set")
  runs=()
  for world in office collapsed; do
    cp "worlds/$world.pgm" "$tmp/"
    for seed in 7 8 9; do
      yaml=$tmp/$world-$set-$seed.yaml
      sed -e "s/laser: {[^}]*}/laser: {$laser}/" -e "s/odometry: {[^}]*}/odometry: {$odometry}/" \
          -e "s/seed: [0-9]*/seed: $seed/" "worlds/$world.yaml" >"$yaml"
      # It prints "robot N: ..." per robot recorded.
      for r in $("$B/cairn_mrlog" from-world --world "$yaml" --routes "worlds/routes/$world.yaml" \
                   --out "${yaml%.yaml}.mrlog" |
                 sed -n 's/^robot \([0-9]*\):.*/\1/p' | sort -u); do
        runs+=("${yaml%.yaml}.mrlog $r")
      done
    done
  done
  ates=()
  for run in "${runs[@]}"; do
    read -r mrlog robot <<<"$run"
    out=$tmp/out-$(basename "$mrlog" .mrlog)-$robot
    "$B/cairn_slam" --mrlog "$mrlog" --robot "$robot" --out "$out" --no-map "$@" >/dev/null
    ate=$("$B/cairn_slam_eval" --estimate "$out/trajectory.csv" --reference-csv "$out/truth.csv" |
          sed -n 's/.*"ate_rmse_m": \([0-9.e-]*\).*/\1/p')
    ates+=("$ate")
  done
  printf '%s\n' "${ates[@]}" | sort -g | awk -v set="$set" \
    '{v[NR] = $1; s += $1} END {printf "%-9s ATE vs truth: mean %.4f m, median %.4f m, worst %.4f m over %d runs\n", set, s / NR, v[int((NR + 1) / 2)], v[NR], NR}'
done
