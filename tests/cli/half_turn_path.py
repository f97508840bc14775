#!/usr/bin/env python3
"""Writes issue 22's path that a coarse ground-truth fit cannot follow, as a TUM pose file (T_world_camera, y up):
standing in the living room, a 180° turn about the vertical in 0.6 s (smoothstep rate, 18 frames), 30 Hz, 3 s.

    half_turn_path.py OUT.tum
"""
import math
import sys

FRAME_PERIOD_S = 1.0 / 30.0
FRAMES = 91
TURN_START_S = 1.0
TURN_S = 0.6
POSITION_M = (1.37, 1.52, -1.45)  # living_room_0's first camera position, inside the room


def main():
    with open(sys.argv[1], "w") as out:
        out.write("# timestamp tx ty tz qx qy qz qw\n")
        for k in range(FRAMES):
            t = k * FRAME_PERIOD_S
            u = min(max((t - TURN_START_S) / TURN_S, 0.0), 1.0)
            yaw = math.pi * u * u * (3.0 - 2.0 * u)
            # Camera z forward, y down: turning about world y (up) by −yaw.
            out.write(f"{t:.6f} {POSITION_M[0]} {POSITION_M[1]} {POSITION_M[2]} 0 {math.sin(-yaw / 2):.12f} 0 "
                      f"{math.cos(-yaw / 2):.12f}\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
