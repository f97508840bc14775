#!/usr/bin/env python3
"""Issue 22's soak: vifusiond over a long replay (`replay_loops`: the sequence end to end, again and again), its
resources sampled every 100 processed frames: resident memory (VmRSS), open file descriptors, threads, and the GPU
arena the daemon logs at start and at exit. Flat after warm-up is the goal: RSS and fds at the last sample within 2 %
of those at frame 1 000, threads and arena unchanged.

usage: soak.py --bin BUILD/bin --dds-config XML --out OUT.json
               [--frames 10000 --width 320 --height 240 --duration 60 --preset long --mode rgbd]
               [--data-dir DIR]   (where the generated sequence is kept; default: beside OUT.json)

Generates the sequence once with `vifusion sim`, runs vifusiond on it as fast as it goes (realtime: false, every
frame in order) until --frames, reads rt/vifusion/status with `vifusion echo` for the frame count, and samples
/proc/PID each time the count passes a multiple of 100. Writes one JSON object: the samples, the comparison with
frame 1 000 (or the first sample past a tenth of the run, for a short smoke run), and whether the goal was met;
exits 1 when the descriptors, the threads or the arena changed (never, whatever the run's length).
"""
import json
import os
import pathlib
import re
import shutil
import sys
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "service"))
from service_harness import Echo, dds_domain_and_partition, fail, start  # noqa: E402

from generated_sequence import frames_in, prepared_sequence, sequence_parser  # noqa: E402

SAMPLE_EVERY_FRAMES = 100
WARM_FRAME = 1000  # issue 22: compared with frame 1 000, after the map, the caches and the allocator settle
RSS_TOLERANCE = 0.02  # ... within 2 %
FD_TOLERANCE = 0.02


def sample(pid, message):
    status = pathlib.Path(f"/proc/{pid}/status").read_text()
    rss_kb = int(re.search(r"^VmRSS:\s+(\d+) kB", status, re.M).group(1))
    threads = int(re.search(r"^Threads:\s+(\d+)", status, re.M).group(1))
    fds = len(os.listdir(f"/proc/{pid}/fd"))
    return {"frames": message["frames_processed"], "rss_kb": rss_kb, "fds": fds, "threads": threads,
            "lost_frames": message["lost_frames"], "surfels": message["surfel_count"]}


def main():
    parser = sequence_parser(__doc__, "long", 60.0, "rgbd")
    parser.add_argument("--frames", type=int, default=10000)
    args = parser.parse_args()
    if args.frames < 10 * SAMPLE_EVERY_FRAMES:
        fail(f"--frames must be at least {10 * SAMPLE_EVERY_FRAMES} to compare a tenth of the run with its end")

    out, data_dir, sequence = prepared_sequence(args)
    per_pass = frames_in(sequence)
    # Run on past the last sample: the frame the daemon stops at is sampled while it writes its outputs and its
    # threads end, which is the stop, not the soak.
    run_frames = args.frames + 2 * SAMPLE_EVERY_FRAMES
    loops = -(-run_frames // per_pass)

    domain, partition = dds_domain_and_partition("soak-bench")
    dds = ["--dds.config", args.dds_config, "--dds.domain", str(domain), "--dds.partition", partition]
    echo_dds = ["--dds-config", args.dds_config, "--domain", str(domain), "--partition", partition]
    timeout_s = args.frames * 2 + 120  # lavapipe at 320x240: far below 1 s a frame
    run_dir = data_dir / f"soak_{args.mode}"
    shutil.rmtree(run_dir, ignore_errors=True)
    log_path = data_dir / f"soak_{args.mode}.log"
    status = Echo(f"{args.bin}/vifusion", "rt/vifusion/status", 0, timeout_s, echo_dds)
    with open(log_path, "w") as log:
        daemon = start([f"{args.bin}/vifusiond", "--source", f"dataset:{sequence}", "--replay_loops", str(loops),
                        "--max_frames", str(run_frames), "--out", str(run_dir), "--mode", args.mode,
                        "--realtime", "false", "--status_period_s", "0.25", "--map_publish_period_s", "0", *dds],
                       stderr=log)
        samples = []
        seen = 0
        started = time.monotonic()
        while daemon.poll() is None:
            if time.monotonic() - started > timeout_s:
                daemon.kill()
                fail(f"the soak did not finish within {timeout_s} s")
            newest = max((m for _, m in status.lines[seen:]), key=lambda m: m["frames_processed"], default=None)
            seen = len(status.lines)
            if newest is not None and newest["frames_processed"] >= (len(samples) + 1) * SAMPLE_EVERY_FRAMES:
                try:
                    samples.append(sample(daemon.pid, newest))
                except (FileNotFoundError, ProcessLookupError):
                    break  # exited between the poll and the read
            time.sleep(0.05)
        code = daemon.wait()
    wall_s = time.monotonic() - started
    status.process.terminate()
    status.wait(10)
    text = log_path.read_text()
    if code != 0:
        fail(f"vifusiond exited with {code}: {text[-2000:]}")
    arena = [int(v) for v in re.findall(r"arena (\d+) bytes", text)]
    if len(samples) < 10 or len(arena) != 2:
        fail(f"{len(samples)} samples, arena logged {len(arena)} times (expected at start and exit)")
    warm_frame = min(WARM_FRAME, args.frames // 10)
    warm = next(s for s in samples if s["frames"] >= warm_frame)
    last = next((s for s in samples if s["frames"] >= args.frames), None)
    if last is None:
        fail(f"no sample at frame {args.frames}: the last was at {samples[-1]['frames']}")
    rss_change = (last["rss_kb"] - warm["rss_kb"]) / warm["rss_kb"]
    fd_change = (last["fds"] - warm["fds"]) / warm["fds"]
    result = {
        "sequence": f"sim:{args.preset} {args.width}x{args.height}, {args.duration:g} s ({per_pass} frames), "
                    f"replayed {loops} times",
        "mode": args.mode,
        "frames": run_frames,
        "wall_s": round(wall_s, 1),
        "frames_per_s": round(run_frames / wall_s, 2),
        "warm": warm,
        "last": last,
        "rss_change": round(rss_change, 5),
        "rss_peak_kb": max(s["rss_kb"] for s in samples if s["frames"] <= last["frames"]),  # not the stop's export
        "fd_change": round(fd_change, 5),
        "threads_change": last["threads"] - warm["threads"],
        "arena_bytes": {"start": arena[0], "exit": arena[1]},
        "goal_met": abs(rss_change) <= RSS_TOLERANCE and abs(fd_change) <= FD_TOLERANCE and
                    last["threads"] == warm["threads"] and arena[0] == arena[1],
        "samples": samples,
    }
    out.write_text(json.dumps(result, indent=2) + "\n")
    print(json.dumps({k: v for k, v in result.items() if k != "samples"}), flush=True)
    # Whatever the run's length, these never move once running: a change is a leak of descriptors or threads.
    if last["fds"] != warm["fds"] or last["threads"] != warm["threads"] or arena[0] != arena[1]:
        fail(f"fds {warm['fds']} -> {last['fds']}, threads {warm['threads']} -> {last['threads']}, "
             f"arena {arena[0]} -> {arena[1]} bytes")


if __name__ == "__main__":
    main()
