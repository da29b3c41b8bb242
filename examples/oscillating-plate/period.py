#!/usr/bin/env python3
"""Oscillating plate: the period from the tip displacement's zero crossings against beam
theory, and the drift of kinetic + internal energy.  Reads plate.dat and plate-info.txt
written by in.plate in the current folder.  Standard library only."""
import re


def read_series(path="plate.dat"):
    rows = []
    with open(path) as f:
        for line in f:
            if not line.startswith("#"):
                c = line.split()
                rows.append([float(v) for v in c[1:]])    # time disp ekin eint etot
    return rows


def crossing_times(t, y):
    """times where y changes sign (linear interpolation)"""
    out = []
    for k in range(1, len(y)):
        if y[k - 1] * y[k] < 0.0:
            out.append(t[k - 1] + (t[k] - t[k - 1]) * y[k - 1] / (y[k - 1] - y[k]))
    return out


def main():
    rows = read_series()
    tbeam = float(re.search(r"period T = ([0-9.eE+-]+)", open("plate-info.txt").read()).group(1))
    t = [r[0] for r in rows]
    disp = [r[1] for r in rows]
    etot = [r[4] for r in rows]
    z = crossing_times(t, disp)    # the tip starts at 0 moving up: crossings every T/2
    tsim = 2.0 * (z[-1] - z[0]) / (len(z) - 1) if len(z) >= 2 else 2.0 * z[0]
    drift = max(abs(e - etot[0]) for e in etot) / abs(etot[0])
    print(f"beam theory period  {tbeam:.5f} s")
    print(f"SPH period          {tsim:.5f} s  ({100.0 * (tsim - tbeam) / tbeam:+.2f} %)")
    print(f"energy drift        {100.0 * drift:.4f} % (kinetic + internal, max over the run)")


if __name__ == "__main__":
    main()
