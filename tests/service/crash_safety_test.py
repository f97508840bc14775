"""Issue 22 item 5: SIGKILL at random moments of `vifusion run` and of vifusiond leaves every file in the output
directory complete: the previous version or the new one, never partial (core/atomic_file.hpp), and the killed
service starts again on what it left and publishes within 10 s.

usage: crash_safety_test.py BIN_DIR SIM_DIR WORK_DIR DDS_CONFIG CASE
CASE: run | service | device_lost
The kill moments are drawn from a fixed seed over the whole of a run, the final writes included. device_lost (item 3):
the GPU lost mid-run (`inject: device-lost@60`) stops vifusiond with exit 4 (systemd's Restart=on-failure restarts
it), the 60 poses before it and the last periodic map save written; the restarted service loads that map and publishes.
"""
import os
import random
import shutil
import signal
import subprocess
import sys
import time

from output_checks import check_directory
from service_harness import Echo, dds_domain_and_partition, fail, main, start, stop

BIN, SIM, WORK, DDS_CONFIG, CASE = sys.argv[1:6]
KILLS = 20
PUBLISH_AGAIN_S = 10.0
def restart_on_map_file(command, domain, partition, after):
    """Starts `command` again with map_file_required true (what the earlier run left must load) and returns the
    seconds until it published its first status; fails past PUBLISH_AGAIN_S."""
    at = command.index("--map_file_required")
    started = time.monotonic()
    daemon = start([*command[:at + 1], "true", *command[at + 2:]], stderr=subprocess.DEVNULL)
    echo = Echo(f"{BIN}/vifusion", "rt/vifusion/status", 1, PUBLISH_AGAIN_S,
                ["--dds-config", DDS_CONFIG, "--domain", str(domain), "--partition", partition])
    if echo.wait(PUBLISH_AGAIN_S + 5) != 0 or not echo.lines:
        fail(f"after {after} the service did not publish again within {PUBLISH_AGAIN_S} s")
    published_s = echo.lines[0][0] - started
    if stop(daemon) != 0:
        fail(f"the restarted service stopped with {daemon.returncode}")
    return published_s


def run_case():
    out = os.path.join(WORK, "crash_run")
    shutil.rmtree(out, ignore_errors=True)
    command = [f"{BIN}/vifusion", "run", "--source", f"dataset:{SIM}", "--mode", "rgbdi", "--out", out,
               "--save-map", os.path.join(out, "map.vifmap")]
    started = time.monotonic()
    first = subprocess.run(command, capture_output=True, text=True)
    whole_s = time.monotonic() - started
    if first.returncode != 0:
        fail(f"the complete run failed ({first.returncode}): {first.stderr[-2000:]}")
    known = set(os.listdir(out))
    if not {"trajectory.txt", "frames.csv", "report.json", "map.ply", "map.vifmap"} <= known:
        fail(f"the complete run wrote {sorted(known)}")
    check_directory(out, known, "the complete run", BIN)
    rng = random.Random(22)
    for kill in range(KILLS):
        process = start(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(rng.uniform(0.0, 1.1 * whole_s))
        process.send_signal(signal.SIGKILL)
        process.wait()
        check_directory(out, known, f"kill {kill} (exit {process.returncode})", BIN)
    print(f"vifusion run: {KILLS} SIGKILLs over {whole_s:.1f} s runs: every file complete", flush=True)


def service_case():
    out = os.path.join(WORK, "crash_service")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    map_file = os.path.join(out, "map.vifmap")
    domain, partition = dds_domain_and_partition("crash-safety-test")
    dds_args = ["--dds.config", DDS_CONFIG, "--dds.domain", str(domain), "--dds.partition", partition]
    command = [f"{BIN}/vifusiond", "--source", f"dataset:{SIM}", "--out", out, "--realtime", "true",
               "--map_file", map_file, "--map_file_required", "false", "--map_save_period_s", "0.5", *dds_args]
    # A first run stopped cleanly leaves trajectory.txt, map.ply and the map file: the previous versions.
    daemon = start(command, stderr=subprocess.DEVNULL)
    time.sleep(3.0)
    if stop(daemon) != 0:
        fail(f"the first run stopped with {daemon.returncode}")
    known = {"trajectory.txt", "map.ply", "map.vifmap"}
    check_directory(out, known, "the first run", BIN)
    rng = random.Random(22)
    for kill in range(KILLS):
        daemon = start(command, stderr=subprocess.DEVNULL)
        time.sleep(rng.uniform(0.0, 3.0))
        daemon.send_signal(signal.SIGKILL)
        daemon.wait()
        check_directory(out, known, f"kill {kill}", BIN)
    # What the kills left is loaded again (map_file_required stays false only so that a first start may create
    # it): the service comes back and publishes.
    published_s = restart_on_map_file(command, domain, partition, f"{KILLS} SIGKILLs")
    print(f"vifusiond: {KILLS} SIGKILLs, every file complete; restarted on the map file and published after "
          f"{published_s:.1f} s", flush=True)


def device_lost_case():
    out = os.path.join(WORK, "device_lost")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    map_file = os.path.join(out, "map.vifmap")
    lost_at = 60  # 2 s in, replayed as fast as it goes (every frame in order): a few periodic saves before it
    domain, partition = dds_domain_and_partition("device-lost-test")
    dds_args = ["--dds.config", DDS_CONFIG, "--dds.domain", str(domain), "--dds.partition", partition]
    command = [f"{BIN}/vifusiond", "--source", f"dataset:{SIM}", "--mode", "rgbdi", "--out", out, "--realtime", "false",
               "--map_file", map_file, "--map_file_required", "false", "--map_save_period_s", "0.5", *dds_args]
    lost = subprocess.run([*command, "--inject", f"device-lost@{lost_at}"], capture_output=True, text=True, timeout=120)
    log = lost.stderr
    if lost.returncode != 4:
        fail(f"exit {lost.returncode} after the device was lost, expected 4 (kExitGpu): {log[-2000:]}")
    if "VK_ERROR_DEVICE_LOST" not in log or "map not saved on stop" not in log:
        fail(f"the log does not say what was lost and kept: {log[-2000:]}")
    with open(os.path.join(out, "trajectory.txt")) as f:
        poses = [line for line in f if not line.startswith("#")]
    if len(poses) != lost_at:
        fail(f"trajectory.txt holds {len(poses)} poses, expected the {lost_at} before the loss")
    check_directory(out, {"trajectory.txt", "states.csv", "map.vifmap"}, "the lost device", BIN)
    if not os.path.exists(map_file):
        fail("no periodic map save before the loss")
    # Restarted (as systemd does after exit 4), without the fault: it loads what was saved and publishes.
    published_s = restart_on_map_file(command, domain, partition, "the lost device")
    print(f"vifusiond: device lost at frame {lost_at}: exit 4, {len(poses)} poses and the map file kept; restarted on "
          f"it and published after {published_s:.1f} s", flush=True)


main({"run": run_case, "service": service_case, "device_lost": device_lost_case}, CASE)
