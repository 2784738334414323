#!/usr/bin/env python3
"""Fails (exit 1) and names every project #include that runs back up a floor.

The floors, bottom up: common -> dds, bag and the cores (sim, robot_agent/core, base_station/core) ->
base_station/{export,store,console} -> the apps (bag/app, sim/app, robot_agent/app, base_station/app).
Each folder below may include only the folders listed for it. Tests (*_test.cpp, *test_util*),
tools/, tests/, bench/ and fuzz/ may reach down anywhere and are not checked.
"""
import pathlib
import re
import subprocess
import sys

# folder (longest prefix wins) -> the project folders its files may include
ALLOWED = {
    "common": ["common"],
    "dds": ["common", "dds"],
    "bag": ["common", "bag"],
    "bag/app": ["common", "dds", "bag"],
    "sim": ["common", "sim"],
    "sim/app": ["common", "dds", "sim"],
    "robot_agent/core": ["common", "robot_agent/core"],
    "robot_agent/app": ["common", "dds", "robot_agent/core", "robot_agent/app"],
    "base_station/core": ["common", "base_station/core"],
    "base_station/export": ["common", "base_station/core", "base_station/export"],
    "base_station/store": ["common", "base_station/store"],
    "base_station/console": ["common", "base_station/core", "base_station/export", "base_station/console"],
    "base_station/app": ["common", "dds", "base_station"],
}
EXEMPT = re.compile(r"(^(tools|tests|bench|fuzz)/)|(_test\.cpp$)|(test_util)")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def floor_of(path):
    best = None
    for folder in ALLOWED:
        if path.startswith(folder + "/") and (best is None or len(folder) > len(best)):
            best = folder
    return best


def main():
    root = pathlib.Path(__file__).resolve().parent.parent
    files = subprocess.run(["git", "ls-files", "*.cpp", "*.h"], cwd=root, check=True, capture_output=True,
                           text=True).stdout.split()
    bad = []
    for path in files:
        floor = floor_of(path)
        if floor is None or EXEMPT.search(path):
            continue
        for number, line in enumerate((root / path).read_text().splitlines(), 1):
            m = INCLUDE.match(line)
            if not m or "/" not in m.group(1):
                continue  # system, generated IDL ("cairn_msgs.h") or same-folder headers
            target = m.group(1)
            if not any(target.startswith(ok + "/") for ok in ALLOWED[floor]):
                bad.append(f"{path}:{number}: includes {target} ({floor} may include {', '.join(ALLOWED[floor])})")
    if bad:
        print("check_floors: %d include(s) run up a floor:" % len(bad), file=sys.stderr)
        print("\n".join(bad), file=sys.stderr)
        return 1
    print(f"check_floors: every include of {len(files)} files stays on its floor or below")
    return 0


if __name__ == "__main__":
    sys.exit(main())
