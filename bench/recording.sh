#!/usr/bin/env bash
# Recording and replay figures (docs/benchmarks.md "Missions as MCAP"): one mission without and one
# with cairn_record (--ros2 --record), then the recording replayed as fast as it goes. Prints the
# recorder's CPU and memory, the missions' total CPU, the file's size per minute of mission against
# the bytes of the samples it holds (the DDS payload), and the replay speed.
# Usage: bench/recording.sh [WORLD]   (default worlds/collapsed.yaml; needs build/)
set -euo pipefail
cd "$(dirname "$0")/.."
world=${1:-worlds/collapsed.yaml}
out=$(mktemp -d /tmp/cairn_bench_recording.XXXX)
bin=build/bin
echo "world $world, results in $out"
$bin/cairn_mission --world "$world" --out "$out/plain" --port 0 > "$out/plain.txt" 2>&1
$bin/cairn_mission --world "$world" --out "$out/rec" --port 0 --ros2 --record "$out/mission.mcap" > "$out/rec.txt" 2>&1
python3 - "$out" <<'PY'
import json, re, sys
out = sys.argv[1]
for run in ("plain", "rec"):
    r = json.load(open(f"{out}/{run}/results.json"))
    cpu = r["cpu_s"]
    print(f"{run:5s}: {r['simulated_s']:.0f} s simulated in {r['wall_s']:.0f} s wall, CPU "
          + ", ".join(f"{k} {v:.1f} s" for k, v in cpu.items()) + f" (total {sum(cpu.values()):.1f} s)")
rec = json.load(open(f"{out}/rec/results.json"))
line = open(f"{out}/rec/logs/record.log").read()
m = re.search(r"(\d+) messages \(([\d.]+) MB of samples\) in (\d+) s -> \S+ \(([\d.]+) MB, (\d+) chunks\)", line)
msgs, samples_mb, secs, file_mb, chunks = int(m[1]), float(m[2]), int(m[3]), float(m[4]), int(m[5])
minutes = rec["simulated_s"] / 60
print(f"recording: {msgs} messages, {samples_mb:.1f} MB of samples -> {file_mb:.1f} MB file ({file_mb / samples_mb:.2f} of "
      f"the samples), {file_mb / minutes:.1f} MB per simulated minute, {chunks} chunks; "
      f"recorder CPU {rec['cpu_s']['record']:.1f} s, peak {rec['peak_rss_kb']['record'] / 1024:.0f} MiB")
PY
domain=$((150 + RANDOM % 80))
$bin/cairn_replay "$out/mission.mcap" --speed 0 --wait 0 --domain $domain 2>&1 | grep -E "replayed" | sed 's/.*info /replay (as fast as possible, no subscriber): /'
