#!/usr/bin/env python3
"""Issue 23's end-to-end smoke of the arm64 build: the arm64 `vifusion` under qemu-aarch64 passes its self-check on
the sysroot's lavapipe, and tracks a second of a small synthetic sequence to the same poses as the build
machine's (x86-64) `vifusion` on the same input.

    arm64_smoke.py HOST_VIFUSION TARGET_VIFUSION WORK_DIR -- EMULATOR...

Both runs read one sequence written by the host's simulator (the whole first second, 30 frames), in rgbdi mode
(dense tracking with the IMU coupled), so the comparison covers the shaders, the reductions and the estimator.
They may differ by rounding: aarch64 contracts a*b + c into fused multiply-adds, x86-64 does not, and a last-bit
difference can flip a discrete decision — a Gauss-Newton solve stopping an iteration earlier (its step within the
estimate's uncertainty, core/step_convergence.hpp), a pixel passing a gate, a surfel's confidence crossing its
threshold — after which the poses differ by micrometres. The tolerance, 0.1 mm and 1e-4 rad per pose, lies well
above that (toolchains/README.md has the measured differences) and well below what tracking resolves: the runs'
own error against the ground truth is millimetres. A defect of the port — a kernel reading
a buffer in another layout, an uninitialised value, another code path — moves poses by millimetres or loses
tracking."""
import math
import os
import shutil
import subprocess
import sys

FRAMES = 30  # the whole 1 s sequence
WIDTH, HEIGHT = 160, 120
MAX_TRANSLATION_M = 1e-4
MAX_ROTATION_RAD = 1e-4


def fail(message):
    print(f"FAIL: {message}", flush=True)
    sys.exit(1)


def run(command, what):
    print("+ " + " ".join(command), flush=True)
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if result.returncode != 0:
        print(result.stdout)
        fail(f"{what} exited with {result.returncode}")
    return result.stdout


def read_poses(path):
    """TUM rows (t tx ty tz qx qy qz qw) keyed by their time stamp as written."""
    poses = {}
    with open(path) as rows:
        for row in rows:
            if row.startswith("#") or not row.strip():
                continue
            fields = row.split()
            poses[fields[0]] = [float(v) for v in fields[1:8]]
    return poses


def rotation_angle(qa, qb):
    """Angle of qa⁻¹·qb in radians for quaternions (x, y, z, w), from the vector part of the product: acos of the
    dot product would turn the files' 1e-9 rounding into 4e-5 rad."""
    na, nb = math.sqrt(sum(v * v for v in qa)), math.sqrt(sum(v * v for v in qb))
    (ax, ay, az, aw), (bx, by, bz, bw) = [v / na for v in qa], [v / nb for v in qb]
    # conj(a) ⊗ b
    w = aw * bw + ax * bx + ay * by + az * bz
    x = aw * bx - ax * bw - ay * bz + az * by
    y = aw * by + ax * bz - ay * bw - az * bx
    z = aw * bz - ax * by + ay * bx - az * bw
    return 2.0 * math.atan2(math.sqrt(x * x + y * y + z * z), abs(w))


def main():
    if len(sys.argv) < 5 or sys.argv[4] != "--":
        fail(__doc__)
    host, target, work = sys.argv[1:4]
    emulator = sys.argv[5:]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    sequence = os.path.join(work, "sequence")

    version_host = run([host, "--version"], "the host's vifusion --version").strip()
    version_target = run(emulator + [target, "--version"], "the arm64 vifusion --version").strip()
    if version_host != version_target:
        fail(f"the arm64 build is '{version_target}', the host's '{version_host}'")
    run(emulator + [target, "selfcheck", "--frames", "2", "--width", str(WIDTH), "--height", str(HEIGHT)],
        "the arm64 vifusion selfcheck")

    run([host, "sim", "--preset", "living_room_0", "--duration", "1", "--width", str(WIDTH), "--height",
         str(HEIGHT), "--out", sequence], "the host's vifusion sim")
    runs = {}
    for name, command in (("x86-64", [host]), ("arm64", emulator + [target])):
        out = os.path.join(work, name)
        run(command + ["run", "--source", f"dataset:{sequence}", "--mode", "rgbdi", "--frames", str(FRAMES), "--out", out],
            f"the {name} vifusion run")
        runs[name] = read_poses(os.path.join(out, "trajectory.txt"))

    reference, ported = runs["x86-64"], runs["arm64"]
    if len(reference) != FRAMES or sorted(reference) != sorted(ported):
        fail(f"the runs wrote different frames: x86-64 {sorted(reference)}, arm64 {sorted(ported)}")
    worst_translation = worst_rotation = 0.0
    for stamp, pose in reference.items():
        other = ported[stamp]
        translation = math.dist(pose[:3], other[:3])
        rotation = rotation_angle(pose[3:], other[3:])
        print(f"t {stamp}: |Δp| {translation * 1e6:.3f} µm, ∠ {rotation:.2e} rad")
        if translation > MAX_TRANSLATION_M or rotation > MAX_ROTATION_RAD:
            fail(f"frame at t {stamp}: the arm64 pose is {translation * 1e6:.3f} µm and {rotation:.2e} rad from the "
                 f"x86-64 one (tolerance {MAX_TRANSLATION_M * 1e6:.0f} µm, {MAX_ROTATION_RAD:.0e} rad)")
        worst_translation = max(worst_translation, translation)
        worst_rotation = max(worst_rotation, rotation)
    print(f"arm64 smoke: selfcheck passed; {FRAMES} rgbdi frames within {worst_translation * 1e6:.3f} µm and "
          f"{worst_rotation:.2e} rad of x86-64 (tolerance {MAX_TRANSLATION_M * 1e6:.0f} µm, {MAX_ROTATION_RAD:.0e} rad)")


if __name__ == "__main__":
    main()
