"""What the service test scripts share: child processes that never outlive the test, `vifusion echo` in
its own process, the facts every odometry stream must show, and a main() that always cleans up."""
import ctypes
import json
import math
import os
import random
import signal
import subprocess
import sys
import threading
import time

SKIP = 77  # ctest SKIP_RETURN_CODE
_processes = []
_cleanups = []


def fail(message):
    print(f"FAIL: {message}", flush=True)
    sys.exit(1)


def skip(message):
    print(f"SKIP: {message}", flush=True)
    sys.exit(SKIP)


def dds_domain_and_partition(tag):
    """A random domain and a partition unique to this run, so parallel runs cannot hear each other.
    The domain comes from the shared range of tests/support/include/vifusion/test/dds_domains.hpp
    (1..228; the domains above are reserved for the tests that count malloc bytes)."""
    return random.randint(1, 228), f"{tag}-{os.getpid()}-{random.randint(0, 1 << 30)}"


_PR_SET_PDEATHSIG = 1  # <linux/prctl.h>
_prctl = ctypes.CDLL(None, use_errno=True).prctl  # resolved here: the child only calls it


def _die_with_parent():
    # In the child before exec: SIGKILL when the test process dies, however it dies (ctest kills only
    # the test at a timeout), so no daemon outlives its test; the setting survives `ip netns exec`.
    _prctl(_PR_SET_PDEATHSIG, signal.SIGKILL)


def start(args, **kwargs):
    print("+", " ".join(args), flush=True)
    process = subprocess.Popen(args, preexec_fn=_die_with_parent, **kwargs)
    _processes.append(process)
    return process


def stop(process, sig=signal.SIGTERM, timeout_s=30):
    process.send_signal(sig)
    return process.wait(timeout_s)


def on_exit(cleanup):
    """Runs `cleanup` when the test ends, after every child process is gone (last registered, first run)."""
    _cleanups.append(cleanup)


class Echo:
    """`vifusion echo TOPIC` in its own process (behind `prefix`, e.g. `ip netns exec NS`); lines are
    collected with their arrival time."""

    def __init__(self, vifusion, topic, count, timeout_s, dds_args, prefix=()):
        self.lines = []
        self.process = start([*prefix, vifusion, "echo", topic, "--count", str(count), "--timeout", str(timeout_s),
                              *dds_args], stdout=subprocess.PIPE, text=True)
        self.thread = threading.Thread(target=self._read, daemon=True)
        self.thread.start()

    def _read(self):
        for line in self.process.stdout:
            self.lines.append((time.monotonic(), json.loads(line)))

    def wait(self, timeout_s):
        code = self.process.wait(timeout_s)
        self.thread.join(5)
        return code


def check_odometry(lines, frame="odom", camera="camera"):
    """Fails unless every echoed nav_msgs/Odometry has a finite pose and the right frames, the stamps
    increase and the camera moves at least 1 mm. Returns (metres moved, stamps [s])."""
    positions = []
    stamps = []
    for _, message in lines:
        p = message["pose"]["pose"]["position"]
        q = message["pose"]["pose"]["orientation"]
        values = [p["x"], p["y"], p["z"], q["x"], q["y"], q["z"], q["w"]]
        if not all(isinstance(v, (int, float)) and math.isfinite(v) for v in values):
            fail(f"non-finite pose {values}")
        positions.append(values[:3])
        stamp = message["header"]["stamp"]
        stamps.append(stamp["sec"] + stamp["nanosec"] * 1e-9)
        if message["header"]["frame_id"] != frame or message["child_frame_id"] != camera:
            fail(f"frame ids are {message['header']['frame_id']} → {message['child_frame_id']}, "
                 f"expected {frame} → {camera}")
    if len(positions) < 2:
        fail(f"{len(positions)} odometry messages: too few to see motion")
    moved = math.dist(positions[0], positions[-1])
    if moved < 1e-3:
        fail(f"the camera does not move: {moved * 1000:.2f} mm over {len(positions)} messages")
    if min(b - a for a, b in zip(stamps, stamps[1:])) <= 0:
        fail("odometry stamps do not increase")
    return moved, stamps


def main(cases, case):
    """Runs cases[case]; prints PASS, or FAIL/SKIP and a non-zero status. Child processes are killed and
    the cleanups run on every path, SIGTERM and SIGINT included (ctest's SIGKILL at a timeout cannot be
    caught: tests/service/netns.py also removes what a killed run left behind)."""
    def interrupted(signum, _frame):
        raise SystemExit(128 + signum)

    signal.signal(signal.SIGTERM, interrupted)
    signal.signal(signal.SIGINT, interrupted)
    try:
        cases[case]()
        print("PASS", flush=True)
    finally:
        for process in _processes:
            if process.poll() is None:
                process.send_signal(signal.SIGCONT)
                process.kill()
                process.wait()
        while _cleanups:
            _cleanups.pop()()
