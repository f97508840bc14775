#!/usr/bin/env python3
"""Issue 20: a camera entering a saved map along another path than the one that built it, where no keyframe
recognises its view, is located by searching the whole map (loop/global_place_search.hpp, Slam::searchMap).

The saved map: 5 s of living_room_0's path (42-47 s: the views nearest to living_room_1's start, 1.1 m away and
20 degrees apart), rgbdi at 160x120. The later run: living_room_1's first second loading it. Checks that the run is
located within 1 s, by the map search (the keyframes did not place it), and in the right place: its ATE in the
saved map's frame (no alignment; both ground truths in the saved run's W) within the ICP's association gate, 0.1 m
(a place verified elsewhere is at least the verification's 0.3 m basin away, or a slide along a surface of
centimetres more than the map's own error).

    check_map_search.py VIFUSION DATA_DIR OUT_DIR
"""
import csv
import json
import os
import shutil
import subprocess
import sys

SEGMENT_S = (42.0, 47.0)
WIDTH, HEIGHT = 160, 120
MAX_LOCATED_AFTER_S = 1.0
MAX_ATE_M = 0.1


def fail(message):
    print("check_map_search: " + message, file=sys.stderr)
    sys.exit(1)


def call(*args):
    result = subprocess.run(list(args), capture_output=True, text=True)
    if result.returncode != 0:
        fail(f"{' '.join(args[:2])} exit {result.returncode}: {result.stderr.strip()[-2000:]}")
    return result.stdout


def ate_in_frame_of(vifusion, dataset, run_dir, origin_dataset):
    out = call(vifusion, "eval", "--gt", os.path.join(dataset, "groundtruth.txt"), "--est",
               os.path.join(run_dir, "trajectory.txt"), "--gt-origin", os.path.join(origin_dataset, "groundtruth.txt"))
    return json.loads(out)["ate_in_origin_frame"]["rmse_m"]


def main():
    vifusion, data_dir, out = sys.argv[1:4]
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    segment = os.path.join(out, "living_room_0_segment.tum")
    with open(os.path.join(data_dir, "icl-nuim-trajectories", "livingRoom0.tum.txt")) as src, open(segment, "w") as dst:
        for line in src:
            # Half a second beyond the end: the simulator's spline needs poses past the last frame.
            if not line.startswith("#") and SEGMENT_S[0] <= float(line.split()[0]) < SEGMENT_S[1] + 0.5:
                dst.write(line)
    size = ["--width", str(WIDTH), "--height", str(HEIGHT)]
    saved_sim, later_sim = os.path.join(out, "saved_sim"), os.path.join(out, "later_sim")
    call(vifusion, "sim", "--trajectory", segment, "--duration", str(SEGMENT_S[1] - SEGMENT_S[0]), *size,
         "--out", saved_sim)
    call(vifusion, "sim", "--preset", "living_room_1", "--data-dir", data_dir, "--duration", "1", *size,
         "--out", later_sim)
    saved_run, later_run = os.path.join(out, "saved_run"), os.path.join(out, "later_run")
    saved_map = os.path.join(saved_run, "map.vifmap")
    call(vifusion, "run", "--mode", "rgbdi", "--source", "dataset:" + saved_sim, "--out", saved_run,
         "--save-map", saved_map)
    call(vifusion, "run", "--mode", "rgbdi", "--source", "dataset:" + later_sim, "--out", later_run,
         "--load-map", saved_map)

    with open(os.path.join(later_run, "report.json")) as f:
        loaded = json.load(f)["loaded_map"]
    print(json.dumps(loaded))
    if not loaded["located"] or loaded["located_after_s"] > MAX_LOCATED_AFTER_S:
        fail(f"not located within {MAX_LOCATED_AFTER_S} s")
    with open(os.path.join(later_run, "frames.csv")) as f:
        rows = list(csv.DictReader(f, fieldnames=None))
    header = [name.lstrip("#") for name in rows[0].keys()]
    rows = [dict(zip(header, row.values())) for row in rows]
    located = next(row for row in rows if row["relocalised"] == "1")
    print(f"located by the map search: {located['map_search_verified']} of {located['map_search_hypotheses']} "
          f"hypotheses verified, cost {located['map_search_cost']}, inlier share {located['map_search_inliers']}")
    if located["map_search_verified"] != "1":
        fail("the located frame was not placed by the map search (a keyframe recognised it: no test of the search)")
    ate = ate_in_frame_of(vifusion, later_sim, later_run, saved_sim)
    saved_ate = ate_in_frame_of(vifusion, saved_sim, saved_run, saved_sim)
    print(f"ATE in the saved map's frame, unaligned: {ate * 1e3:.1f} mm (the saving run's own: {saved_ate * 1e3:.1f} mm)")
    if ate > MAX_ATE_M:
        fail(f"ATE in the saved frame {ate:.3f} m > {MAX_ATE_M} m: located in the wrong place")


if __name__ == "__main__":
    main()
