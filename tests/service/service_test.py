#!/usr/bin/env python3
"""vifusiond, vifusion-health and `vifusion echo` as separate processes on the loopback interface.

usage: service_test.py BIN_DIR SIM_DIR WORK_DIR DDS_CONFIG CASE
CASE: odometry | odometry_health | sigterm_sigkill | stall
DDS_CONFIG is a Cyclone XML that keeps DDS on lo (../shared/dds/loopback.xml, or the installed
/etc/vifusion/cyclonedds.xml for `odometry`). Every case uses a random DDS domain and a unique
partition, so parallel runs cannot hear each other.
"""
import hashlib
import json
import os
import signal
import subprocess
import sys
import time

from service_harness import Echo, check_odometry, dds_domain_and_partition, fail, main, start, stop

BIN, SIM, WORK, DDS_CONFIG, CASE = sys.argv[1:6]
DOMAIN, PARTITION = dds_domain_and_partition("service-test")
DDS_ARGS = ["--dds.config", DDS_CONFIG, "--dds.domain", str(DOMAIN), "--dds.partition", PARTITION]
ECHO_ARGS = ["--dds-config", DDS_CONFIG, "--domain", str(DOMAIN), "--partition", PARTITION]


def echo(topic, count, timeout_s):
    return Echo(f"{BIN}/vifusion", topic, count, timeout_s, ECHO_ARGS)


def daemon(out, *extra):
    return start([f"{BIN}/vifusiond", "--source", f"dataset:{SIM}", "--out", out, "--realtime", "true",
                  "--frame_ring", "64", *DDS_ARGS, *extra])


def health():
    # A lost-tracking streak is not what these tests are about (160×120 tracks poorly): only the
    # heartbeat, frame rate and overrun rules decide.
    return start([f"{BIN}/vifusion-health", *DDS_ARGS, "--health.min_frame_rate_hz", "1",
                  "--health.lost_error_s", "1000"])


def sha(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def evaluate(out):
    """The eval command reads trajectory.txt with eval::readTum and map.ply with eval::readPlyPositions."""
    result = subprocess.run([f"{BIN}/vifusion", "eval", "--gt", f"{SIM}/groundtruth.txt", "--est",
                             f"{out}/trajectory.txt", "--map", f"{out}/map.ply"], capture_output=True, text=True)
    if result.returncode != 0:
        fail(f"vifusion eval cannot read {out}: {result.stderr.strip()}")
    return json.loads(result.stdout)


def odometry_only():
    """Odometry reaches a reader with this DDS configuration (the installed default: tests/systemd)."""
    stream = echo("rt/vifusion/odometry", 10, 40)
    service = daemon(f"{WORK}/odometry-{os.getpid()}")
    if stream.wait(45) != 0:
        fail(f"echo received {len(stream.lines)} of 10 odometry messages with {DDS_CONFIG}")
    moved, stamps = check_odometry(stream.lines)
    print(f"odometry with {DDS_CONFIG}: {len(stamps)} messages, moved {moved * 1000:.1f} mm", flush=True)
    code = stop(service)
    if code != 0:
        fail(f"vifusiond exited with {code} after SIGTERM")


def odometry_health():
    monitor = health()
    diagnostics = echo("rt/diagnostics", 0, 25)
    odometry = echo("rt/vifusion/odometry", 10, 40)
    map_chunk = echo("rt/vifusion/map", 1, 40)
    service = daemon(f"{WORK}/odometry", "--map_publish_period_s", "1")
    if odometry.wait(45) != 0:
        fail(f"echo received {len(odometry.lines)} of 10 odometry messages")
    moved, stamps = check_odometry(odometry.lines)
    steps = [b - a for a, b in zip(stamps, stamps[1:])]
    wall = odometry.lines[-1][0] - odometry.lines[0][0]
    rate = (len(stamps) - 1) / wall if wall > 0 else float("inf")
    print(f"odometry: moved {moved * 1000:.1f} mm over {stamps[-1] - stamps[0]:.3f} s of data; "
          f"received at {rate:.1f} Hz; stamp steps {min(steps) * 1000:.1f}..{max(steps) * 1000:.1f} ms", flush=True)
    # Realtime pacing: never faster than the data's 30 Hz (with a margin for delivery jitter), and
    # fast enough to be frame-rate output rather than a trickle.
    if not 2.0 <= rate <= 45.0:
        fail(f"odometry arrives at {rate:.1f} Hz, expected the data's frame rate (30 Hz) or somewhat below")
    code = service.wait(60)
    if code != 0:
        fail(f"vifusiond exited with {code} at the end of the source")
    diagnostics.process.terminate()
    diagnostics.wait(10)
    # Transient-local: the last map chunk reaches the reader whenever it was published.
    if map_chunk.wait(10) != 0:
        fail("no rt/vifusion/map chunk")
    cloud = map_chunk.lines[0][1]
    print(f"map: {cloud['width']} points, point_step {cloud['point_step']}", flush=True)
    if cloud["header"]["frame_id"] != "map" or cloud["point_step"] != 36:
        fail("map chunk has the wrong frame or layout")
    all_ok = [m for _, m in diagnostics.lines if m["status"] and all(s["level"] == 0 for s in m["status"])]
    print(f"diagnostics: {len(diagnostics.lines)} arrays, {len(all_ok)} with every rule OK", flush=True)
    if not all_ok:
        fail("rt/diagnostics never reported every rule OK while vifusiond ran")
    names = {s["name"] for s in all_ok[0]["status"]}
    for rule in ("vifusion: heartbeat", "vifusion: frame rate", "vifusion: tracking", "vifusion: ring overruns"):
        if rule not in names:
            fail(f"no diagnostic status '{rule}'")
    stop(monitor)


def sigterm_sigkill():
    out = f"{WORK}/sigterm"
    os.makedirs(out, exist_ok=True)
    for name in os.listdir(out):
        os.remove(os.path.join(out, name))
    # First run: SIGTERM mid-run → files written, exit 0.
    odometry = echo("rt/vifusion/odometry", 20, 40)
    service = daemon(out)
    if odometry.wait(45) != 0:
        fail("first run: no odometry")
    started = time.monotonic()
    code = stop(service)
    print(f"first run: SIGTERM → exit {code} after {time.monotonic() - started:.2f} s", flush=True)
    if code != 0:
        fail(f"SIGTERM: exit code {code}")
    with open(f"{out}/trajectory.txt") as f:
        poses = [line for line in f if not line.startswith("#")]
    frames = sum(1 for _ in open(f"{SIM}/rgb.txt") if not _.startswith("#"))
    if not 20 <= len(poses) < frames:
        fail(f"trajectory.txt has {len(poses)} poses; expected a mid-run stop (>= 20, < {frames})")
    report = evaluate(out)
    print(f"first run: {len(poses)} poses, eval: {json.dumps(report)[:200]}", flush=True)
    before = {name: sha(f"{out}/{name}") for name in ("trajectory.txt", "map.ply")}

    # Second run into the same directory: SIGKILL mid-run leaves the first run's files untouched.
    odometry = echo("rt/vifusion/odometry", 10, 40)
    service = daemon(out)
    if odometry.wait(45) != 0:
        fail("second run: no odometry")
    stop(service, signal.SIGKILL)
    after = {name: sha(f"{out}/{name}") for name in ("trajectory.txt", "map.ply")}
    if after != before:
        fail("SIGKILL changed the previous run's trajectory.txt or map.ply")
    leftovers = sorted(set(os.listdir(out)) - {"trajectory.txt", "map.ply"})
    if any(not name.endswith(".tmp") for name in leftovers):
        fail(f"unexpected files after SIGKILL: {leftovers}")
    evaluate(out)
    print(f"second run: SIGKILL left both files unchanged (other files: {leftovers})", flush=True)


def stall():
    monitor = health()
    odometry = echo("rt/vifusion/odometry", 5, 40)
    service = daemon(f"{WORK}/stall")
    if odometry.wait(45) != 0:
        fail("no odometry")
    diagnostics = echo("rt/diagnostics", 0, 30)
    time.sleep(1.0)  # echo discovers the health daemon
    service.send_signal(signal.SIGSTOP)
    stopped = time.monotonic()
    flagged = []
    # Resume well within the pipeline's 60 s GPU wait, which counts the stopped time as a hang.
    while not flagged and time.monotonic() < stopped + 3.0:
        time.sleep(0.05)
        flagged = [t for t, m in list(diagnostics.lines) if t > stopped and any(
            s["name"] == "vifusion: heartbeat" and s["level"] >= 2 for s in m["status"])]
    service.send_signal(signal.SIGCONT)
    diagnostics.process.terminate()
    diagnostics.wait(10)
    code = stop(service)
    if not flagged:
        fail("rt/diagnostics never went to ERROR/STALE after SIGSTOP")
    delay = flagged[0] - stopped
    print(f"stall flagged {delay:.2f} s after SIGSTOP; vifusiond exit {code} after SIGCONT+SIGTERM", flush=True)
    if delay > 2.0:
        fail(f"stall flagged only after {delay:.2f} s (limit 2 s)")
    if code != 0:
        fail(f"vifusiond exit code {code}")
    stop(monitor)


main({"odometry": odometry_only, "odometry_health": odometry_health, "sigterm_sigkill": sigterm_sigkill,
      "stall": stall}, CASE)
