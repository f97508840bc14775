#!/usr/bin/env python3
"""Issue 20 end to end on the 2 s synthetic living room: a run that loads the map an earlier run saved of the
same frames relocalises into it and tracks in its frame; `vifusion eval --gt-origin` gives the ATE in that
frame without alignment. With --localisation-only the run tracks against the map without changing it: the map
file is byte-identical afterwards and the map on the GPU keeps its surfel count.

    check_reload.py VIFUSION DATASET SAVED_RUN_DIR OUT_DIR [--localisation-only]
"""
import hashlib
import json
import os
import shutil
import subprocess
import sys

# The bounds: located within 1 s; ATE in the saved map's frame within 1.5× that of the run that mapped
# from scratch, both unaligned in the same frame (the saved run's W): a run tracked against the map cannot be
# closer to the truth there than the map itself, whose own error (drift, the simulated depth bias's scale)
# alignment would hide.
MAX_LOCATED_AFTER_S = 1.0
MAX_ATE_RATIO = 1.5


def fail(message):
    print("check_reload: " + message, file=sys.stderr)
    sys.exit(1)


def ate_in_saved_frame(vifusion, dataset, run_dir):
    """RMSE [m] of run_dir's trajectory against the dataset's ground truth in the frame of its first pose."""
    gt = os.path.join(dataset, "groundtruth.txt")
    evaluation = subprocess.run([vifusion, "eval", "--gt", gt, "--est", os.path.join(run_dir, "trajectory.txt"),
                                 "--gt-origin", gt], capture_output=True, text=True)
    if evaluation.returncode != 0:
        fail(f"eval exit {evaluation.returncode}: {evaluation.stderr.strip()}")
    return json.loads(evaluation.stdout)["ate_in_origin_frame"]["rmse_m"]


def main():
    vifusion, dataset, saved_run, out = sys.argv[1:5]
    localisation_only = sys.argv[5:] == ["--localisation-only"]
    shutil.rmtree(out, ignore_errors=True)
    saved_map = os.path.join(saved_run, "map.vifmap")
    with open(saved_map, "rb") as f:
        before = hashlib.sha256(f.read()).hexdigest()
    run = subprocess.run([vifusion, "run", "--mode", "rgbdi", "--source", "dataset:" + dataset, "--out", out,
                          "--load-map", saved_map, *(["--localisation-only"] if localisation_only else [])],
                         capture_output=True, text=True)
    if run.returncode != 0:
        fail(f"run exit {run.returncode}: {run.stderr.strip()[-2000:]}")
    with open(os.path.join(out, "report.json")) as f:
        report = json.load(f)
    loaded = report["loaded_map"]
    print(json.dumps(loaded))
    with open(os.path.join(saved_run, "report.json")) as f:
        saved = json.load(f)
    if loaded["surfels"] != saved["map_file"]["surfels"] or loaded["keyframes"] != saved["map_file"]["keyframes"]:
        fail("the loaded map is not the saved one")
    if not loaded["located"] or loaded["located_after_s"] > MAX_LOCATED_AFTER_S:
        fail(f"not located within {MAX_LOCATED_AFTER_S} s")
    reloaded_ate = ate_in_saved_frame(vifusion, dataset, out)
    scratch_ate = ate_in_saved_frame(vifusion, dataset, saved_run)
    print(f"ATE in the saved map's frame, unaligned: reload {reloaded_ate * 1e3:.1f} mm, the run that mapped from "
          f"scratch {scratch_ate * 1e3:.1f} mm (aligned: {report['ate_rmse_m'] * 1e3:.1f} and "
          f"{saved['ate_rmse_m'] * 1e3:.1f} mm); surfels {saved['surfels']} saved, {report['surfels']} after the reload")
    if reloaded_ate > MAX_ATE_RATIO * scratch_ate:
        fail(f"ATE in the saved frame {reloaded_ate} m > {MAX_ATE_RATIO} × {scratch_ate} m")
    if report["surfels"] > 1.1 * saved["surfels"]:
        fail(f"the map doubled: {saved['surfels']} → {report['surfels']} surfels over the same frames")
    if localisation_only:
        with open(saved_map, "rb") as f:
            after = hashlib.sha256(f.read()).hexdigest()
        if after != before:
            fail("localisation only: the map file changed")
        if not report["localisation_only"] or report["surfels"] != loaded["surfels"]:
            fail(f"localisation only: the map went from {loaded['surfels']} to {report['surfels']} surfels")
        print(f"localisation only: the map file byte-identical (sha256 {after[:16]}…), {report['surfels']} surfels")


if __name__ == "__main__":
    main()
