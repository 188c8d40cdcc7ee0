#!/usr/bin/env python3
"""Solve the QPs of a `sulcus-cli qp-gen` file with DAQP, the way `qp-bench`
solves them with Sulcus's solver, and print both side by side.

Each frame is  min 1/2 (q - q_h)^T G (q - q_h)  s.t.  A q >= b,  given to DAQP
as H = G, f = -G q_h, b <= A q <= +inf. Along each sequence DAQP is warm-started
from the previous frame's multipliers (its `dual_start`), as Sulcus's solver is
from the previous frame's active set. Times are DAQP's own (measured in C, not
Python's call overhead): its setup (it factors H and scales A for every new A,
which a haptic frame has) and its solve. The ratio is Sulcus's time over DAQP's
setup plus solve, and over its solve alone.

Usage: daqp_bench.py QP_FILE SULCUS_SOLUTIONS SULCUS_MEDIAN_US SULCUS_P99_US
(the solutions file and the two figures come from `sulcus-cli qp-bench FILE
--solutions SULCUS_SOLUTIONS`). Prints one line of figures.
"""
import struct
import sys

import numpy as np
import daqp


def read_instances(path):
    with open(path, "rb") as f:
        data = f.read()
    if len(data) < 16:
        raise SystemExit(f"{path}: too short for a QP file header (16 bytes)")
    n, m, seqs, frames = struct.unpack_from("<4i", data, 0)
    stride = n * (1 + m) + m
    want = 16 + 8 * (n + seqs * frames * stride)
    if min(n, m, seqs, frames) <= 0 or len(data) != want:
        raise SystemExit(f"{path}: {len(data)} bytes, expected {want} for n={n} m={m} S={seqs} T={frames}")
    g = np.frombuffer(data, dtype="<f8", count=n, offset=16).copy()
    body = np.frombuffer(data, dtype="<f8", offset=16 + 8 * n).reshape(seqs, frames, stride).copy()
    return n, m, g, body


def percentile(sorted_values, q):
    return sorted_values[min(len(sorted_values) - 1, int(q * len(sorted_values)))]


def main():
    if len(sys.argv) != 5:
        raise SystemExit(__doc__)
    path, solutions, ours_median, ours_p99 = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
    n, m, g, body = read_instances(path)
    seqs, frames = body.shape[0], body.shape[1]
    ours = np.fromfile(solutions, dtype="<f8")
    if ours.size != seqs * frames * n:
        raise SystemExit(f"{solutions}: {ours.size} values, expected {seqs * frames * n}")
    ours = ours.reshape(seqs, frames, n)
    H = np.diag(g)
    upper = np.full(m, 1e30)
    setup_solve, solve_only = [], []
    failures, iterations, worst_diff = 0, 0, 0.0
    for s in range(seqs):
        lam = None
        for t in range(frames):
            frame = body[s, t]
            qh, A, b = frame[:n], frame[n:n + n * m].reshape(m, n), frame[n + n * m:]
            kwargs = {"dual_start": lam} if lam is not None else {}
            x, _, exitflag, info = daqp.solve(H, -g * qh, np.array(A), upper, np.array(b),
                                              **kwargs)
            setup_solve.append(1e6 * (info["setup_time"] + info["solve_time"]))
            solve_only.append(1e6 * info["solve_time"])
            iterations += info["iterations"]
            if exitflag != 1:
                failures += 1
                lam = None
                continue
            lam = info["lam"]
            worst_diff = max(worst_diff, float(np.max(np.abs(np.asarray(x) - ours[s, t]))))
    setup_solve.sort()
    solve_only.sort()
    med, p99 = percentile(setup_solve, 0.5), percentile(setup_solve, 0.99)
    smed, sp99 = percentile(solve_only, 0.5), percentile(solve_only, 0.99)
    print(f"daqp setup+solve median {med:.2f} us, p99 {p99:.2f} us (solve alone {smed:.2f} / {sp99:.2f}); "
          f"iterations mean {iterations / len(solve_only):.2f}; failures {failures}; "
          f"sulcus {ours_median:.2f} / {ours_p99:.2f} us; "
          f"ratio sulcus/daqp median {ours_median / med:.2f}, p99 {ours_p99 / p99:.2f} "
          f"(against solve alone {ours_median / smed:.2f}, {ours_p99 / sp99:.2f}); "
          f"largest solution difference {worst_diff:.1e}")


if __name__ == "__main__":
    main()
