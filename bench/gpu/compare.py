#!/usr/bin/env python3
"""Compare two per-atom dumps written by in.collision (sorted by id): max position difference
relative to the body size, max velocity difference relative to the largest speed, and the max
difference of each state column relative to that column's largest magnitude.
Usage: compare.py A.dump B.dump [tolerance]  (exit 1 when a difference exceeds the tolerance)"""
import sys
import numpy as np

def load(path):
    with open(path) as f:
        lines = f.readlines()
    k = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS"))
    cols = lines[k].split()[2:]
    return cols, np.loadtxt(lines[k + 1:])

ca, a = load(sys.argv[1])
cb, b = load(sys.argv[2])
tol = float(sys.argv[3]) if len(sys.argv) > 3 else 1e-8
assert ca == cb and a.shape == b.shape, "different atoms or columns"
assert (a[:, 0] == b[:, 0]).all(), "different atom IDs"
size = np.ptp(a[:, 1])
worst = 0.0
report = []
dx = np.abs(a[:, 1:4] - b[:, 1:4]).max() / size
report.append(("x", dx))
dv = np.abs(a[:, 4:7] - b[:, 4:7]).max() / np.abs(a[:, 4:7]).max()
report.append(("v", dv))
for j, name in enumerate(ca[7:], start=7):
    scale = np.abs(a[:, j]).max()
    if scale > 0:
        report.append((name, np.abs(a[:, j] - b[:, j]).max() / scale))
for name, d in report:
    worst = max(worst, d)
print(f"{len(a)} atoms; " + ", ".join(f"{n} {d:.2e}" for n, d in report))
print(f"max relative difference {worst:.3e} (tolerance {tol:g}): {'PASS' if worst <= tol else 'FAIL'}")
sys.exit(0 if worst <= tol else 1)
