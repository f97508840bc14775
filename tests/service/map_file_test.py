#!/usr/bin/env python3
"""vifusiond's map file (config map_file): saved while running, on request and on stop; loaded at the next start,
which relocalises into it and keeps its world frame; a missing or damaged file refused by name.

usage: map_file_test.py BIN_DIR SIM_DIR WORK_DIR DDS_CONFIG CASE
CASE: save_load | refused
Each case uses a random DDS domain and a unique partition (service_harness.py).
"""
import hashlib
import json
import math
import os
import shutil
import subprocess
import sys
import time

from service_harness import Echo, dds_domain_and_partition, fail, main, start

BIN, SIM, WORK, DDS_CONFIG, CASE = sys.argv[1:6]
DOMAIN, PARTITION = dds_domain_and_partition("map-file-test")
DDS_ARGS = ["--dds.config", DDS_CONFIG, "--dds.domain", str(DOMAIN), "--dds.partition", PARTITION]
CLI_DDS_ARGS = ["--dds-config", DDS_CONFIG, "--domain", str(DOMAIN), "--partition", PARTITION]
EXIT_MAP = 8  # config::kExitMap
# The second start begins this far into the sequence, where the camera has turned away from the first start's first
# pose (W in rgbd mode): an empty map would put its first camera at W's origin, the saved one where the first start
# tracked it. The check is at the last frame both tracked: the same W agrees there within the tracking's own noise
# on 160x120 frames (mm, tenths of a degree); a new W would differ by the whole motion before LATER_START_S (7 deg
# of turn; 2 s in, 16 deg from the map's only keyframe, relocalisation rightly finds no place).
LATER_START_S = 1.5
SAME_WORLD_M = 0.05
SAME_WORLD_DEG = 3.0
NOWHERE_S = 2.5
TRACKING_RELOCALISING = 4  # vifusion_msgs/Status


def daemon(out, map_file, *extra, realtime=True, sim=SIM):
    os.makedirs(out, exist_ok=True)
    return start([f"{BIN}/vifusiond", "--source", f"dataset:{sim}", "--out", out, "--realtime",
                  "true" if realtime else "false", "--frame_ring", "64", "--map_file", map_file,
                  "--log_file", f"{out}/vifusiond.log", *DDS_ARGS, *extra])


def log_of(out):
    with open(f"{out}/vifusiond.log") as f:
        return f.read()


def map_info(path):
    result = subprocess.run([f"{BIN}/vifusion", "map", "info", path], capture_output=True, text=True)
    if result.returncode != 0:
        fail(f"vifusion map info {path}: exit {result.returncode}: {result.stderr.strip()}")
    return json.loads(result.stdout)


def sha(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def trajectory(out):
    """{stamp: (position, unit quaternion xyzw)} of trajectory.txt (TUM: t x y z qx qy qz qw)."""
    with open(f"{out}/trajectory.txt") as f:
        rows = [line.split() for line in f if not line.startswith("#")]
    if not rows:
        fail(f"{out}/trajectory.txt has no pose")
    return {round(float(r[0]), 4): ([float(v) for v in r[1:4]], [float(v) for v in r[4:8]]) for r in rows}


def angle_deg(q, r):
    """The rotation angle between two unit quaternions [deg]."""
    return math.degrees(2 * math.acos(min(1.0, abs(sum(a * b for a, b in zip(q, r))))))


def later_start(sim, dst, start_s):
    """The same dataset from start_s on: the frame lists trimmed, everything else linked."""
    os.makedirs(dst)
    for name in os.listdir(sim):
        if name not in ("rgb.txt", "depth.txt"):
            os.symlink(os.path.join(sim, name), os.path.join(dst, name))
    for name in ("rgb.txt", "depth.txt"):
        with open(os.path.join(sim, name)) as f, open(os.path.join(dst, name), "w") as out:
            out.writelines(line for line in f if line.startswith("#") or float(line.split()[0]) >= start_s - 1e-6)


def fresh(path):
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(path)
    return path


def save_load():
    work = fresh(f"{WORK}/map_file_save_load")
    map_file = f"{work}/robot.vifmap"

    # First start: no file yet (map_file_required: false creates it); every frame in order (realtime false: the same
    # map on any machine), saved every 0.2 s while running and on stop at the end of the source.
    status = Echo(f"{BIN}/vifusion", "rt/vifusion/status", 0, 120, CLI_DDS_ARGS)
    first = f"{work}/first"
    code = daemon(first, map_file, "--map_file_required", "false", "--map_save_period_s", "0.2",
                  realtime=False).wait(120)
    status.process.terminate()
    status.wait(10)
    if code != 0:
        fail(f"first start: vifusiond exited with {code}:\n{log_of(first)}")
    log = log_of(first)
    if "starting with an empty map" not in log:
        fail("first start: no file yet, but the log does not say it starts with an empty map")
    saves = [line for line in log.splitlines() if "map saved to" in line]
    last = max((m for _, m in status.lines), key=lambda m: m["heartbeat"]) if status.lines else None
    print(f"first start: {len(saves)} saves logged, the last: {saves[-1:]}; last status: "
          f"{ {k: last[k] for k in last if k.startswith('map_')} if last else None}", flush=True)
    if len(saves) < 2 or "failed" in log or "not saved" in log:
        fail(f"first start: {len(saves)} saves logged (expected periodic ones and the stop's)")
    if last is None or last["map_saves"] < 1 or last["map_save_failures"] != 0 or last["map_file_bytes"] <= 0 \
            or last["map_capture_ms"] <= 0 or last["map_write_ms"] <= 0:
        fail(f"first start: the status does not report the saves: {last}")
    saved = map_info(map_file)
    if saved["surfels"] <= 0 or saved["frames"] <= 0:
        fail(f"first start: the map file holds {saved['surfels']} surfels, {saved['frames']} frames")
    if any(name.endswith(".tmp") for name in os.listdir(work)):
        fail(f"a temporary file was left beside the map file: {os.listdir(work)}")
    print(f"first start: {map_file}: {saved['surfels']} surfels, {saved['keyframes']} keyframes, "
          f"{saved['bytes']} bytes", flush=True)

    # Second start, LATER_START_S into the same frames: loads the file (required: the default), relocalises into
    # it, keeps its W, and saves the extended map on stop.
    second = f"{work}/second"
    later = f"{work}/later_start"
    later_start(SIM, later, LATER_START_S)
    code = daemon(second, map_file, "--map_save_period_s", "0", realtime=False, sim=later).wait(120)
    if code != 0:
        fail(f"second start: vifusiond exited with {code}:\n{log_of(second)}")
    log = log_of(second)
    for expected in ("loaded", "located in the loaded map", "map saved to"):
        if expected not in log:
            fail(f"second start: the log lacks '{expected}':\n{log}")
    before, after = trajectory(first), trajectory(second)
    common = sorted(set(before) & set(after))
    if not common:
        fail("second start: no frame in common with the first start's trajectory")
    stamp = common[-1]
    offset_m = math.dist(before[stamp][0], after[stamp][0])
    offset_deg = angle_deg(before[stamp][1], after[stamp][1])
    turned_deg = angle_deg(before[min(before)][1], before[min(after)][1])
    print(f"second start: at {stamp} s {offset_m * 1000:.1f} mm and {offset_deg:.2f} deg from the first start's pose "
          f"(same W: < {SAME_WORLD_M * 1000:.0f} mm, < {SAME_WORLD_DEG} deg; the camera had turned {turned_deg:.1f} "
          f"deg before the second start's first frame)", flush=True)
    if turned_deg < 2 * SAME_WORLD_DEG:
        fail(f"the camera turned only {turned_deg:.1f} deg before the second start: too little to tell a new W")
    if offset_m > SAME_WORLD_M or offset_deg > SAME_WORLD_DEG:
        fail(f"second start: not in the saved map's frame at {stamp} s")
    resaved = map_info(map_file)
    print(f"second start: saved again, {saved['surfels']} -> {resaved['surfels']} surfels", flush=True)
    if not saved["surfels"] * 0.5 <= resaved["surfels"] <= saved["surfels"] * 1.5:
        fail(f"second start: the map went from {saved['surfels']} to {resaved['surfels']} surfels over frames it "
             f"had mapped")

    # Localisation only (mapping: false) over the first start's frames: tracked in the saved W, the file untouched, a
    # save request answered without a save.
    unchanged = sha(map_file)
    localising = f"{work}/localisation_only"
    service = daemon(localising, map_file, "--mapping", "false")
    request = subprocess.run([f"{BIN}/vifusion", "map", "save", "--timeout", "60", *CLI_DDS_ARGS],
                             capture_output=True, text=True, timeout=90)
    code = service.wait(120)
    if code != 0:
        fail(f"localisation only: vifusiond exited with {code}:\n{log_of(localising)}")
    if request.returncode != 1 or "localisation only" not in request.stdout:
        fail(f"localisation only: vifusion map save answered exit {request.returncode}: {request.stdout}")
    if sha(map_file) != unchanged or "map saved" in log_of(localising):
        fail("localisation only: the map file was written")
    # Paced at the camera's rate (the request needs the service running), so frames may be skipped on a loaded
    # machine: the RMS over the frames it tracked, against the first start's poses of the same frames.
    tracked = trajectory(localising)
    offsets = [math.dist(before[t][0], tracked[t][0]) for t in set(before) & set(tracked)]
    rms_m = math.sqrt(sum(d * d for d in offsets) / len(offsets))
    print(f"localisation only: {len(tracked)} poses, {rms_m * 1000:.1f} mm RMS (max {max(offsets) * 1000:.1f} mm) from "
          f"the first start's; the file unchanged; {request.stdout.strip()}", flush=True)
    if rms_m > SAME_WORLD_M:
        fail(f"localisation only: {rms_m:.3f} m RMS from the first start's poses over the same frames")

    # Third start, NOWHERE_S into the frames: turned further from every saved keyframe than a place guess may be
    # corrected (dense_tracker.hpp max_place_correction_rad, 11.5 deg), so the camera is never located. The service
    # says so in its status (TRACKING_RELOCALISING), vifusion-health warns, nothing else is published, and the file
    # is left as loaded.
    unchanged = sha(map_file)
    nowhere = f"{work}/nowhere"
    later_start(SIM, nowhere, NOWHERE_S)
    monitor = start([f"{BIN}/vifusion-health", *DDS_ARGS, "--health.min_frame_rate_hz", "1"])
    status = Echo(f"{BIN}/vifusion", "rt/vifusion/status", 0, 60, CLI_DDS_ARGS)
    diagnostics = Echo(f"{BIN}/vifusion", "rt/diagnostics", 0, 60, CLI_DDS_ARGS)
    published = [Echo(f"{BIN}/vifusion", topic, 0, 60, CLI_DDS_ARGS)
                 for topic in ("rt/vifusion/odometry", "rt/vifusion/pose", "rt/tf")]
    time.sleep(1.0)  # the readers discover each other before the frames start
    code = daemon(f"{work}/relocalising", map_file, sim=nowhere).wait(120)
    time.sleep(0.5)  # the last diagnostics
    for echo in (status, diagnostics, *published):
        echo.process.terminate()
        echo.wait(10)
    monitor.terminate()
    monitor.wait(10)
    if code != 0:
        fail(f"never located: vifusiond exited with {code}:\n{log_of(f'{work}/relocalising')}")
    states = [m["tracking_state"] for _, m in status.lines if m["frames_processed"] > 0]
    warnings = [s["message"] for _, m in diagnostics.lines for s in m["status"]
                if s["name"] == "vifusion: tracking" and s["level"] == 1 and "relocalising" in s["message"]]
    print(f"never located: tracking_state in {len(states)} statuses: {sorted(set(states))}; health: {warnings[-1:]}; "
          f"published {[len(e.lines) for e in published]} odometry/pose/tf messages", flush=True)
    if not states or set(states) != {TRACKING_RELOCALISING}:
        fail(f"never located: the status said {sorted(set(states))}, expected only {TRACKING_RELOCALISING}")
    if not warnings:
        fail("never located: vifusion-health did not warn that the service is relocalising")
    if any(e.lines for e in published):
        fail("never located: a pose was published before the camera was located in the loaded map")
    if sha(map_file) != unchanged:
        fail("never located: the map file changed although nothing was mapped into it")

    # Fourth start, paced at the camera's rate: `vifusion map save` against the running service is answered by a save.
    fourth = f"{work}/fourth"
    service = daemon(fourth, map_file, "--map_save_period_s", "0")
    request = subprocess.run([f"{BIN}/vifusion", "map", "save", "--timeout", "60", *CLI_DDS_ARGS],
                             capture_output=True, text=True, timeout=90)
    print(request.stdout, end="", flush=True)
    code = service.wait(120)
    if request.returncode != 0 or "saved" not in request.stdout:
        fail(f"vifusion map save against the running service: exit {request.returncode}: {request.stdout}"
             f"{request.stderr}\n{log_of(fourth)}")
    if code != 0:
        fail(f"fourth start: vifusiond exited with {code}:\n{log_of(fourth)}")
    requested = [line for line in log_of(fourth).splitlines() if "map save request" in line]
    if not requested:
        fail("fourth start: the log does not show the request")
    map_info(map_file)


def refused():
    work = fresh(f"{WORK}/map_file_refused")
    map_file = f"{work}/robot.vifmap"

    # Missing, required (the default): the start is refused, naming the file.
    out = f"{work}/missing"
    code = daemon(out, map_file, "--max_frames", "5").wait(120)
    log = log_of(out)
    if code != EXIT_MAP or "no such file" not in log or map_file not in log:
        fail(f"missing map file, required: exit {code} (expected {EXIT_MAP}), log:\n{log}")
    print(f"missing, required: exit {code}", flush=True)

    # A sound file from a short run, then one byte flipped inside its surfels.
    out = f"{work}/make"
    code = daemon(out, map_file, "--max_frames", "10", "--map_file_required", "false", realtime=False).wait(120)
    if code != 0:
        fail(f"making a map file: exit {code}:\n{log_of(out)}")
    end_section_header = 24  # the end section: a header, no payload (README "Map file layout")
    with open(map_file, "r+b") as f:
        f.seek(-(end_section_header + 100), os.SEEK_END)
        byte = f.read(1)
        f.seek(-1, os.SEEK_CUR)
        f.write(bytes([byte[0] ^ 0x10]))
    damaged = sha(map_file)

    out = f"{work}/damaged_required"
    code = daemon(out, map_file, "--max_frames", "5").wait(120)
    log = log_of(out)
    if code != EXIT_MAP or "surfels" not in log:
        fail(f"damaged map file, required: exit {code} (expected {EXIT_MAP}) naming the surfels section; log:\n{log}")
    if sha(map_file) != damaged:
        fail("a refused start changed the map file")
    print(f"damaged, required: exit {code}: "
          f"{[line for line in log.splitlines() if 'cannot be loaded' in line][0]}", flush=True)

    # Not required: the service starts with an empty map, the damaged file kept aside, a new one saved.
    out = f"{work}/damaged_optional"
    code = daemon(out, map_file, "--max_frames", "10", "--map_file_required", "false", realtime=False).wait(120)
    log = log_of(out)
    if code != 0 or "refused" not in log:
        fail(f"damaged map file, not required: exit {code}; log:\n{log}")
    if not os.path.exists(f"{map_file}.refused") or sha(f"{map_file}.refused") != damaged:
        fail(f"the refused file was not kept as {map_file}.refused")
    map_info(map_file)
    print("damaged, not required: started empty, the damaged file kept as .refused, a new map saved", flush=True)


main({"save_load": save_load, "refused": refused}, CASE)
