#!/usr/bin/env python3
"""Independent reference for the TUM ATE RMSE, used to pin the number in test_metrics.cpp.

Standard library only, and deliberately a different algorithm from the C++ path: the C++ code
aligns with an SVD of the cross-covariance (evaluate_ate.py), this script uses Horn's (1987)
closed-form quaternion method — the rotation is the eigenvector of the largest eigenvalue of a
symmetric 4x4 matrix, found with a cyclic Jacobi eigen-solver. Timestamps stay Python floats in
seconds, as in associate.py (the C++ code uses integer nanoseconds).

Usage: tum_ate_reference.py GROUNDTRUTH ESTIMATE [--max_difference 0.02]
Prints the ATE RMSE [m] and the number of associated pairs.
"""
import argparse
import math


def read_tum(path):
    """{stamp [s]: (tx, ty, tz)} as associate.py reads it: ',' and tabs are spaces, '#' lines skipped."""
    poses = {}
    with open(path, encoding="utf-8") as f:
        text = f.read().replace(",", " ").replace("\t", " ")
    for line in text.split("\n"):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        fields = [float(v) for v in line.split()]
        poses[fields[0]] = tuple(fields[1:4])
    return poses


def associate(first, second, max_difference):
    """associate.py: candidates under max_difference, smallest |dt| first, each stamp used once."""
    candidates = sorted(
        (abs(a - b), a, b) for a in first for b in second if abs(a - b) < max_difference)
    used_a, used_b, matches = set(), set(), []
    for _, a, b in candidates:
        if a not in used_a and b not in used_b:
            used_a.add(a)
            used_b.add(b)
            matches.append((a, b))
    matches.sort()
    return matches


def jacobi_eigen(a):
    """Eigenvalues and column eigenvectors of a symmetric matrix (cyclic Jacobi rotations)."""
    n = len(a)
    a = [row[:] for row in a]
    v = [[1.0 if i == j else 0.0 for j in range(n)] for i in range(n)]
    for _ in range(100):
        off = sum(a[i][j] ** 2 for i in range(n) for j in range(n) if i != j)
        if off < 1e-30:
            break
        for p in range(n - 1):
            for q in range(p + 1, n):
                if abs(a[p][q]) < 1e-300:
                    continue
                theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q])
                t = math.copysign(1.0, theta) / (abs(theta) + math.sqrt(theta * theta + 1.0))
                c = 1.0 / math.sqrt(t * t + 1.0)
                s = t * c
                for k in range(n):  # A <- A J
                    akp, akq = a[k][p], a[k][q]
                    a[k][p], a[k][q] = c * akp - s * akq, s * akp + c * akq
                for k in range(n):  # A <- J^T A
                    apk, aqk = a[p][k], a[q][k]
                    a[p][k], a[q][k] = c * apk - s * aqk, s * apk + c * aqk
                for k in range(n):  # V <- V J
                    vkp, vkq = v[k][p], v[k][q]
                    v[k][p], v[k][q] = c * vkp - s * vkq, s * vkp + c * vkq
    return [a[i][i] for i in range(n)], v


def horn_align(model, data):
    """R, t minimising sum |R m_i + t - d_i|^2 (Horn 1987, unit quaternions)."""
    count = len(model)
    m_mean = [sum(p[k] for p in model) / count for k in range(3)]
    d_mean = [sum(p[k] for p in data) / count for k in range(3)]
    s = [[0.0] * 3 for _ in range(3)]  # s[a][b] = sum m'_a d'_b
    for m, d in zip(model, data):
        for a in range(3):
            for b in range(3):
                s[a][b] += (m[a] - m_mean[a]) * (d[b] - d_mean[b])
    (sxx, sxy, sxz), (syx, syy, syz), (szx, szy, szz) = s
    n = [[sxx + syy + szz, syz - szy, szx - sxz, sxy - syx],
         [syz - szy, sxx - syy - szz, sxy + syx, szx + sxz],
         [szx - sxz, sxy + syx, -sxx + syy - szz, syz + szy],
         [sxy - syx, szx + sxz, syz + szy, -sxx - syy + szz]]
    values, vectors = jacobi_eigen(n)
    best = max(range(4), key=lambda i: values[i])
    w, x, y, z = (vectors[k][best] for k in range(4))
    r = [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
         [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
         [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]
    t = [d_mean[a] - sum(r[a][b] * m_mean[b] for b in range(3)) for a in range(3)]
    return r, t


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("groundtruth")
    parser.add_argument("estimate")
    parser.add_argument("--max_difference", type=float, default=0.02)
    args = parser.parse_args()
    gt = read_tum(args.groundtruth)
    est = read_tum(args.estimate)
    matches = associate(gt, est, args.max_difference)
    data = [gt[a] for a, _ in matches]
    model = [est[b] for _, b in matches]
    r, t = horn_align(model, data)
    squared = 0.0
    for m, d in zip(model, data):
        e = [sum(r[a][b] * m[b] for b in range(3)) + t[a] - d[a] for a in range(3)]
        squared += sum(v * v for v in e)
    print(f"pairs {len(matches)}")
    print(f"ate_rmse_m {math.sqrt(squared / len(matches)):.9f}")


if __name__ == "__main__":
    main()
