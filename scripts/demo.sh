#!/usr/bin/env bash
# The main job: installs the stack, builds, and runs a simulated multi-robot rescue mission end to
# end (simulator, one agent per robot, base station, each its own process over Fast DDS), then
# prints the results and the console URL. Extra arguments go to cairn_mission, e.g.
#   scripts/demo.sh --serve                         keep the console up afterwards
#   scripts/demo.sh --world worlds/office.yaml      the small office floor
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh
./scripts/build.sh
world=worlds/collapsed.yaml
for arg in "$@"; do [ "$arg" = "--world" ] && world=""; done
exec ./build/bin/cairn_mission ${world:+--world "$world"} "$@"
