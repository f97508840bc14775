#!/usr/bin/env python3
"""Issue 18: vifusiond records its source while it maps (`record: true`) and keeps up: every frame and IMU
sample it was handed is in the recording, none lost to a full ring. Reports MB/s, CPU time (the whole daemon and
the recorder's own thread) and what was dropped, as one JSON object.

usage: record_while_mapping.py --bin BUILD/bin --dds-config XML --out OUT.json
               [--preset living_room_0 --width 640 --height 480 --duration 10 --mode rgbdi]
               [--data-dir DIR]  (where the generated sequence is kept; default: beside OUT.json)
               [--keep]          (keep the daemon's recording; by default it is removed once checked)

The source is `vifusion sim --out SEQ.mcap` (generated once), replayed by vifusiond as `rec:SEQ.mcap` at its
timestamps (realtime: true: 30 frames/s of depth + colour, IMU at 200 Hz) while it maps on the GPU, with
`record: true`. Then Foxglove's own reader (tests/node/read_recording.mjs: @mcap/core, rosmsg2-serialization)
decodes the source and the daemon's recording: every frame must be in it with the same stamp and the same depth
and colour bytes (FNV-1a), and the IMU samples the mapped frames took must be the source's, in order. vifusiond's
closing log line gives the recorder's counts: nothing may be lost to a full ring. Exit 1 when anything is.
"""
import json
import os
import pathlib
import re
import resource
import shutil
import subprocess
import sys
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "service"))
from service_harness import dds_domain_and_partition, fail, start  # noqa: E402

from generated_sequence import generate, sequence_parser  # noqa: E402

NODE_DIR = pathlib.Path(__file__).resolve().parent.parent / "node"
CLOSING_LINE = re.compile(
    r"recording (?P<path>\S+): (?P<frames>\d+) frames, (?P<imu>\d+) IMU samples, (?P<edges>\d+) sync edges, "
    r"(?P<mb>[\d.]+) MB; not recorded \(full rings, or after a failure\): (?P<frames_lost>\d+) frames, "
    r"(?P<imu_lost>\d+) IMU samples; recorder thread CPU (?P<recorder_cpu_s>[\d.]+) s")
EXIT_LINE = re.compile(r"exiting with code (\d+) after (\d+) frames \((\d+) lost\)")


def decoded(node, path):
    """What Foxglove's libraries read from the recording `path` (read_recording.mjs's JSON)."""
    result = subprocess.run([node, str(NODE_DIR / "read_recording.mjs"), str(path)], capture_output=True, text=True)
    if result.returncode != 0:
        fail(f"read_recording.mjs {path}: {result.stderr.strip()}")
    return json.loads(result.stdout)


def last_trajectory_stamp_ns(trajectory):
    """The stamp of the last pose in a TUM trajectory file [ns]."""
    rows = [line.split() for line in trajectory.read_text().splitlines() if line.strip() and line[0] != "#"]
    if not rows:
        fail(f"{trajectory}: no pose")
    return round(float(rows[-1][0]) * 1e9)


def main():
    parser = sequence_parser(__doc__, "living_room_0", 10.0, "rgbdi")
    parser.set_defaults(width=640, height=480)
    parser.add_argument("--keep", action="store_true", help="keep the daemon's recording")
    args = parser.parse_args()
    if args.mode == "rgbd":
        fail("--mode rgbd records no IMU samples: use rgbdi or gyro")
    node = shutil.which("node") or shutil.which("nodejs")
    if node is None:
        fail("Node.js is not installed: run .ci/install-deps")

    out = pathlib.Path(args.out).resolve()
    data_dir = pathlib.Path(args.data_dir).resolve() if args.data_dir else out.parent
    data_dir.mkdir(parents=True, exist_ok=True)
    source = data_dir / f"{args.preset}_{args.width}x{args.height}_{args.duration:g}s.mcap"
    generate(args.bin, args.preset, args.width, args.height, args.duration, source)
    run_dir = out.parent / f"record_while_mapping_{args.mode}"
    shutil.rmtree(run_dir, ignore_errors=True)
    run_dir.mkdir(parents=True)
    log_path = run_dir / "vifusiond.log"

    domain, partition = dds_domain_and_partition("record-bench")
    timeout_s = args.duration * 10 + 120  # paced at 1× the sequence, plus start-up and the final frames
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.monotonic()
    with open(log_path, "w") as log:
        daemon = start([f"{args.bin}/vifusiond", "--source", f"rec:{source}", "--mode", args.mode, "--realtime",
                        "true", "--record", "true", "--record_dir", str(run_dir / "recordings"), "--out",
                        str(run_dir), "--map_publish_period_s", "0", "--dds.config", args.dds_config,
                        "--dds.domain", str(domain), "--dds.partition", partition], stderr=log)
        try:
            code = daemon.wait(timeout_s)
        except subprocess.TimeoutExpired:
            daemon.kill()
            fail(f"vifusiond did not finish within {timeout_s:g} s; log: {log_path}")
    wall_s = time.monotonic() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    text = log_path.read_text()
    if code != 0:
        fail(f"vifusiond exited with {code}: {text[-2000:]}")
    closing = CLOSING_LINE.search(text)
    exiting = EXIT_LINE.search(text)
    if closing is None or exiting is None:
        fail(f"vifusiond's log lacks the recording's closing line or the exit line: {log_path}")
    recording = pathlib.Path(closing["path"])

    # Foxglove's reader on both files: the same frames, byte for byte, and the source's IMU samples in order.
    want = decoded(node, source)
    got = decoded(node, recording)
    problems = []
    if got["frames"] != want["frames"]:
        first = next((i for i, (g, w) in enumerate(zip(got["frames"], want["frames"])) if g != w),
                     min(len(got["frames"]), len(want["frames"])))
        problems.append(f"frames differ from the source's: {len(got['frames'])} recorded, "
                        f"{len(want['frames'])} in the source, first difference at frame {first}")
    if got["imu"] != want["imu"][:len(got["imu"])]:
        problems.append("the recorded IMU samples are not the source's first ones, in order")
    # The SLAM thread hands over the samples the frames it maps take: through the first one after its last frame.
    mapped_through_ns = last_trajectory_stamp_ns(run_dir / "trajectory.txt")
    taken = sum(1 for sample in want["imu"] if int(sample["t_ns"]) <= mapped_through_ns)
    if len(got["imu"]) < taken:
        problems.append(f"{len(got['imu'])} IMU samples recorded, but the mapped frames took {taken}")
    frames_lost = int(closing["frames_lost"])
    imu_lost = int(closing["imu_lost"])
    if frames_lost or imu_lost:
        problems.append(f"lost to full rings: {frames_lost} frames, {imu_lost} IMU samples")

    recorded_bytes = recording.stat().st_size
    cpu_s = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    result = {
        "sequence": f"sim:{args.preset} {args.width}x{args.height}, {args.duration:g} s, rec: at its timestamps",
        "mode": args.mode,
        "cores": os.cpu_count(),
        "wall_s": round(wall_s, 2),
        "source_frames": len(want["frames"]),
        "frames_recorded": len(got["frames"]),
        "imu_recorded": len(got["imu"]),
        "frames_mapped": int(exiting.group(2)),
        "mb_recorded": round(recorded_bytes / 1e6, 1),
        "mb_per_s": round(recorded_bytes / 1e6 / args.duration, 1),  # the source's pace: its duration
        "process_cpu_ms_per_s": round(cpu_s * 1e3 / wall_s, 1),
        "recorder_cpu_ms_per_s": round(float(closing["recorder_cpu_s"]) * 1e3 / args.duration, 1),
        "frames_dropped": frames_lost,
        "imu_dropped": imu_lost,
        "goal_met": not problems,
    }
    out.write_text(json.dumps(result, indent=2) + "\n")
    print(json.dumps(result), flush=True)
    if problems:
        fail("; ".join(problems) + f" (recording kept: {recording})")
    if not args.keep:
        recording.unlink()


if __name__ == "__main__":
    main()
