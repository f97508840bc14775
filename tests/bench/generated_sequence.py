"""The benchmarks' generated sequences: `vifusion sim` run once into a directory kept between runs."""
import argparse
import pathlib
import shutil
import subprocess


def generate(bin_dir, preset, width, height, duration, target):
    """`vifusion sim` into `target` — a dataset directory, or a recording when it ends in .mcap — unless a complete
    one is there (written beside it, then renamed)."""
    recording = target.suffix == ".mcap"
    if (target.exists() if recording else (target / "calibration.yaml").exists()):
        return
    partial = target.with_name(target.stem + ".partial" + target.suffix)
    if recording:
        partial.unlink(missing_ok=True)
    else:
        shutil.rmtree(partial, ignore_errors=True)
    subprocess.run([f"{bin_dir}/vifusion", "sim", "--preset", preset, "--width", str(width), "--height", str(height),
                    "--duration", str(duration), "--out", str(partial)], check=True, stdout=subprocess.DEVNULL)
    partial.rename(target)


def frames_in(sequence):
    """The sequence's frame count (its rgb.txt rows)."""
    with open(sequence / "rgb.txt") as f:
        return sum(1 for line in f if line.strip() and not line.startswith("#"))


def sequence_parser(doc, preset, duration_s, mode):
    """The options every daemon benchmark takes: binaries, DDS config, output, and the sequence to generate."""
    parser = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--bin", required=True, help="directory holding vifusion and vifusiond")
    parser.add_argument("--dds-config", required=True, help="Cyclone DDS XML (the loopback config)")
    parser.add_argument("--out", required=True, help="JSON file to write")
    parser.add_argument("--preset", default=preset)
    parser.add_argument("--width", type=int, default=320)
    parser.add_argument("--height", type=int, default=240)
    parser.add_argument("--duration", type=float, default=duration_s, help="seconds of the sequence")
    parser.add_argument("--mode", default=mode, choices=["rgbd", "rgbdi", "gyro"])
    parser.add_argument("--data-dir", help="where the generated sequence is kept (default: beside --out)")
    return parser


def prepared_sequence(args):
    """Generates the sequence the parsed options name (once, under --data-dir or beside --out) and returns
    (the output file, the data directory, the sequence directory)."""
    if args.duration <= 0:
        raise SystemExit(f"--duration must be > 0 s, got {args.duration}")
    out = pathlib.Path(args.out).resolve()
    data_dir = pathlib.Path(args.data_dir).resolve() if args.data_dir else out.parent
    data_dir.mkdir(parents=True, exist_ok=True)
    sequence = data_dir / f"{args.preset}_{args.width}x{args.height}_{args.duration:g}s"
    generate(args.bin, args.preset, args.width, args.height, args.duration, sequence)
    return out, data_dir, sequence
