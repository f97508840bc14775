#!/usr/bin/env python3
"""Growth of a loaded map over the area a second run revisits (issue 20's "the map does not double").

Usage: revisit_growth.py SAVED.vifmap LATER.vifmap SCRATCH.ply GT_SAVED GT_LATER

SAVED.vifmap is the first run's map file, LATER.vifmap the map file after the run that loaded it, SCRATCH.ply the
second run's own map made from scratch (in its own first camera's frame), GT_SAVED and GT_LATER the two runs' ground
truth (TUM; their first poses are the two frames' origins). The revisited area: the saved map's stable surfels'
5 cm voxels that the scratch map also occupies (moved into the saved frame by the ground truth, dilated one voxel
for its drift). Counted are stable surfels (confidence >= 10, as the PLY export): in the later map, those created
before the saved map's frame clock (the saved ones, however they were fused since) and after it (new); a new one is
"on a saved disk" when its centre lies on a saved stable surfel's disk (within 1 cm of its plane, in-plane distance
below its radius, normals within 30 degrees): the saved surface mapped a second time; otherwise it fills a hole.
Reads the map files' meta and surfels sections (pipeline/mapfile map_sections.hpp); no checksums are checked
(`vifusion map info` does that)."""
import math
import struct
import sys

VOXEL_M, CELL_M, PLANE_M, STABLE = 0.05, 0.03, 0.01, 10.0
COS_30 = math.cos(math.radians(30.0))


def section(data, tag):
    """Payload offset of the section with this tag (8 bytes, NUL-padded) in a map file."""
    offset = 16  # file header
    while offset < len(data):
        name, size = struct.unpack_from('<8sQ', data, offset)
        if name.rstrip(b'\0') == tag:
            return offset + 24
        offset += 24 + size
    sys.exit(f"no section '{tag.decode()}'")


def read_map(path):
    """(frame clock, surfels as 12-tuples: x y z confidence nx ny nz radius colour created updated pad)."""
    data = open(path, 'rb').read()
    if data[:8] != b'VIFUSMAP':
        sys.exit(f'{path}: not a map file')
    meta = section(data, b'meta')
    mode_bytes = struct.unpack_from('<I', data, meta)[0]
    clock = struct.unpack_from('<I', data, meta + 4 + mode_bytes)[0]
    surfels = section(data, b'surfels')
    count = struct.unpack_from('<I', data, surfels)[0]
    record = struct.Struct('<12f')
    return clock, [record.unpack_from(data, surfels + 12 + k * record.size) for k in range(count)]


def read_ply_points(path):
    with open(path, 'rb') as f:
        count = 0
        while True:
            line = f.readline().decode().strip()
            if line.startswith('element vertex'):
                count = int(line.split()[2])
            if line == 'end_header':
                break
        record = struct.Struct('<6f3B2f')
        data = f.read(record.size * count)
        return [record.unpack_from(data, k * record.size)[:3] for k in range(count)]


def first_pose(path):
    for line in open(path):
        if not line.startswith('#') and line.strip():
            v = list(map(float, line.split()))
            return v[1:4], v[4:8]
    sys.exit(f'{path}: no pose')


def rotation(q):
    x, y, z, w = q
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def key(p, size):
    return (math.floor(p[0] / size), math.floor(p[1] / size), math.floor(p[2] / size))


def main():
    if len(sys.argv) != 6:
        sys.exit(__doc__)
    saved_path, later_path, scratch_path, gt_saved, gt_later = sys.argv[1:6]
    t0, q0 = first_pose(gt_saved)
    t1, q1 = first_pose(gt_later)
    r0, r1 = rotation(q0), rotation(q1)

    def into_saved(p):  # the later run's frame -> world -> the saved run's frame
        w = [sum(r1[i][j] * p[j] for j in range(3)) + t1[i] for i in range(3)]
        d = [w[i] - t0[i] for i in range(3)]
        return [sum(r0[j][i] * d[j] for j in range(3)) for i in range(3)]

    seen = set()
    for p in read_ply_points(scratch_path):
        k = key(into_saved(p), VOXEL_M)
        seen.update((k[0] + dx, k[1] + dy, k[2] + dz) for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1))
    clock, saved_all = read_map(saved_path)
    saved = [s for s in saved_all if s[3] >= STABLE]
    per_voxel = {}
    for s in saved:
        per_voxel[key(s, VOXEL_M)] = per_voxel.get(key(s, VOXEL_M), 0) + 1
    revisited = {k for k in per_voxel if k in seen}
    saved_there = sum(per_voxel[k] for k in revisited)
    cells = {}
    for s in saved:
        cells.setdefault(key(s, CELL_M), []).append(s)
    later_clock, later = read_map(later_path)
    kept = new = on_disk = 0
    for r in later:
        if r[3] < STABLE or key(r, VOXEL_M) not in revisited:
            continue
        if r[9] < clock:
            kept += 1
            continue
        new += 1
        c = key(r, CELL_M)
        near = (s for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1)
                for s in cells.get((c[0] + dx, c[1] + dy, c[2] + dz), ()))
        for s in near:
            if r[4] * s[4] + r[5] * s[5] + r[6] * s[6] < COS_30:
                continue
            d = (r[0] - s[0], r[1] - s[1], r[2] - s[2])
            h = d[0] * s[4] + d[1] * s[5] + d[2] * s[6]
            if abs(h) < PLANE_M and d[0] ** 2 + d[1] ** 2 + d[2] ** 2 - h * h < s[7] ** 2:
                on_disk += 1
                break
    print(f'saved map: {len(saved_all)} surfels ({len(saved)} stable), frame clock {clock}; '
          f'later map: {len(later)} surfels, frame clock {later_clock}')
    print(f'revisited: {len(revisited)} of {len(per_voxel)} voxels of {VOXEL_M * 100:.0f} cm, '
          f'{saved_there} saved stable surfels there')
    print(f'later map there: {kept} saved, {new} new ({100.0 * new / saved_there:+.1f} %): {on_disk} on a saved disk '
          f'({100.0 * on_disk / saved_there:+.1f} %), {new - on_disk} in holes ({100.0 * (new - on_disk) / saved_there:+.1f} %)')


if __name__ == '__main__':
    main()
