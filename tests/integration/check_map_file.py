#!/usr/bin/env python3
"""Checks a map file saved by `vifusion run --save-map` against the run's report.json through
`vifusion map info`, then damages copies of it and expects the section named (exit 2).

    check_map_file.py VIFUSION RUN_DIR MAP_FILE
"""
import json
import os
import shutil
import subprocess
import sys

FILE_HEADER_BYTES = 16     # map_file_format.hpp
SECTION_HEADER_BYTES = 24
SURFEL_BYTES = 48          # map/surfel.hpp
SECTIONS = ["meta", "calib", "state", "traj", "keyframe", "surfels", "end"]


def fail(message):
    print("check_map_file: " + message, file=sys.stderr)
    sys.exit(1)


def map_info(vifusion, path):
    return subprocess.run([vifusion, "map", "info", path], capture_output=True, text=True)


def expect_refused(vifusion, path, words):
    result = map_info(vifusion, path)
    if result.returncode != 2 or not all(w in result.stderr for w in words):
        fail(f"{path}: expected exit 2 naming {words}, got {result.returncode}: {result.stderr.strip()}")
    print("refused as expected: " + result.stderr.strip())


def main():
    vifusion, run_dir, map_path = sys.argv[1:4]
    with open(os.path.join(run_dir, "report.json")) as f:
        report = json.load(f)
    result = map_info(vifusion, map_path)
    if result.returncode != 0:
        fail(f"map info exit {result.returncode}: {result.stderr.strip()}")
    info = json.loads(result.stdout)
    print(json.dumps(info))
    saved = report["map_file"]
    checks = {
        "file size": (info["bytes"], os.path.getsize(map_path)),
        "report's size": (info["bytes"], saved["bytes"]),
        "surfels vs the report's map": (info["surfels"], report["surfels"]),
        "surfels vs the save": (info["surfels"], saved["surfels"]),
        "surfels section size": (info["section_bytes"]["surfels"], 12 + SURFEL_BYTES * info["surfels"]),
        "keyframes": (info["keyframes"], report["relocalisation"]["keyframes"]),
        "poses": (info["trajectory_poses"], report["frames"]),
        "frames": (info["frames"], report["frames"]),
        "mode": (info["mode"], report["mode"]),
        "estimator state": (info["estimator_state"], report["mode"] != "rgbd"),
        "format version": (info["format_version"], 1),
    }
    for name, (got, expected) in checks.items():
        if got != expected:
            fail(f"{name}: map info says {got}, expected {expected}")
    if info["surfels"] == 0 or info["keyframes"] == 0:
        fail("the saved map is empty")

    # Where each section's payload lies (the documented layout).
    offset, payloads = FILE_HEADER_BYTES, {}
    for name in SECTIONS:
        payloads[name] = (offset + SECTION_HEADER_BYTES, info["section_bytes"][name])
        offset += SECTION_HEADER_BYTES + info["section_bytes"][name]
    if offset != info["bytes"]:
        fail(f"sections end at {offset}, the file at {info['bytes']}")

    damaged = map_path + ".damaged"
    with open(map_path, "rb") as f:
        sound = f.read()
    for name in ["surfels", "keyframe", "traj"]:
        start, size = payloads[name]
        flipped = bytearray(sound)
        flipped[start + size // 2] ^= 0x40
        with open(damaged, "wb") as f:
            f.write(flipped)
        expect_refused(vifusion, damaged, [damaged, f"section '{name}'", "corrupt"])
        with open(damaged, "wb") as f:
            f.write(sound[: start + size // 2])
        expect_refused(vifusion, damaged, [f"section '{name}': cut"])
    os.remove(damaged)


if __name__ == "__main__":
    main()
