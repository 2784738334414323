#!/usr/bin/env bash
# The slow-radio matrix (docs/benchmarks.md "The slow radio"): one mission per cell of loss x rate
# behind the emulated radio (cairn_mission --link-loss/--link-kbit; needs root, nft, tc). For each
# cell: keyframes and objects the base stored of those each robot sent, the time from a victim's
# confirmation on its robot to its arrival at the base (both logs stamp the same host clock), wall
# time, and the bytes that crossed the radio towards the base over the robots' payload.
# Usage: bench/radio_matrix.sh [WORLD] [SPEED] [CELLS]
#   WORLD default tests/worlds/two_robots_meet.yaml; SPEED default 1 (real time: the robots send
#   what real ones would; 0 = as fast as the simulator goes); CELLS default "0/1000 10/1000 30/1000
#   0/250 10/250 30/250 10/100 10/250/60+60" (loss %/kbit/s[/cut at s+for s, wall time]).
set -euo pipefail
cd "$(dirname "$0")/.."
world=${1:-tests/worlds/two_robots_meet.yaml}
speed=${2:-1}
cells=${3:-"0/1000 10/1000 30/1000 0/250 10/250 30/250 10/100 10/250/60+60"}
out=$(mktemp -d /tmp/cairn_bench_radio.XXXX)
echo "world $world at speed $speed, results in $out"
echo "| loss | kbit/s | cut | delivered keyframes | delivered objects | victim to base (median / max) | wall | overhead | exit |"
echo "|---|---|---|---|---|---|---|---|---|"
for cell in $cells; do
  IFS=/ read -r loss kbit cut <<< "$cell"
  cut_args=()
  [ -n "$cut" ] && cut_args=(--link-cut "${cut%+*}" "${cut#*+}")
  dir="$out/loss${loss}_kbit${kbit}${cut:+_cut$cut}"
  set +e
  build/bin/cairn_mission --world "$world" --out "$dir" --port 0 --speed "$speed" --timeout 1500 \
    --link-loss "$loss" --link-kbit "$kbit" "${cut_args[@]}" > "$dir.txt" 2>&1
  code=$?
  set -e
  python3 - "$dir" "$loss" "$kbit" "${cut:--}" "$code" <<'PY'
import glob, json, re, statistics, sys
d, loss, kbit, cut, code = sys.argv[1:]
def stamp(line):
    m = re.match(r"\[(\d+):(\d+):(\d+)\.(\d+)\]", line)
    return int(m[1]) * 3600 + int(m[2]) * 60 + int(m[3]) + int(m[4]) / 1000 if m else None
try:
    summary = json.load(open(f"{d}/map/summary.json"))
    results = json.load(open(f"{d}/results.json"))
except (OSError, ValueError):
    print(f"| {loss} | {kbit} | {cut} | - | - | - | - | - | {code} (no results) |")
    sys.exit(0)
kf = ob = kf_sent = ob_sent = 0
for r in summary["robots"]:
    kf += r["keyframes"]; kf_sent += r["link"]["keyframes_sent"]
    ob += r["object_reports"]; ob_sent += r["link"]["objects_sent"]
# A victim's confirmation on its robot, and its first line at the base ("victim 0 from robot1").
confirmed = {}
for path in glob.glob(f"{d}/logs/agent*.log"):
    robot = int(re.search(r"agent(\d+)\.log", path)[1])
    for line in open(path):
        m = re.search(r"object (\d+) \(victim\) confirmed", line)
        if m: confirmed.setdefault((robot, int(m[1])), stamp(line))
latency = []
seen = set()
for line in open(f"{d}/logs/base.log"):
    m = re.search(r"victim (\d+) from robot(\d+)", line)
    if m and (int(m[2]), int(m[1])) in confirmed and (int(m[2]), int(m[1])) not in seen:
        seen.add((int(m[2]), int(m[1])))
        latency.append(stamp(line) - confirmed[(int(m[2]), int(m[1]))])
lat = f"{statistics.median(latency):.1f} / {max(latency):.1f} s ({len(latency)} of {len(confirmed)})" if latency else "none arrived"
radio = results.get("radio", {})
print(f"| {loss} | {kbit} | {cut} | {kf}/{kf_sent} | {ob}/{ob_sent} | {lat} | {results['wall_s']:.0f} s | "
      f"{radio.get('overhead', 0):.2f}x | {code} |")
PY
done
