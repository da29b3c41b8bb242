#!/usr/bin/env python3
"""The last frame of dump.milling (particles coloured by temperature) with the cutter's outline from
the last cutter-*.vtk that fix contact/tri-penalty wrote, into picture.png.  Run in the output folder."""
import glob
import os
import re
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
from dump2vtu import last_frame  # noqa: E402


def tool_segments(path):
    with open(path) as f:
        t = f.read().split()
    i = t.index("POINTS")
    npnt = int(t[i + 1])
    xyz = [float(v) for v in t[i + 3:i + 3 + 3 * npnt]]
    pts = [(xyz[3 * k], xyz[3 * k + 1]) for k in range(npnt)]
    j = t.index("CELLS")
    ncell = int(t[j + 1])
    segs, p = [], j + 3
    for _ in range(ncell):
        m = int(t[p])
        ids = [int(v) for v in t[p + 1:p + 1 + m]]
        segs.append([pts[q] for q in ids])
        p += 1 + m
    return segs


def main():
    step, cols, rows = last_frame("dump.milling")
    if rows is None:
        sys.exit("picture.py: no frame in dump.milling (run with -var dumpevery N)")
    x, y, T = cols.index("x"), cols.index("y"), cols.index("temperature")
    fig, ax = plt.subplots(figsize=(7, 5))
    sc = ax.scatter([r[x] * 1e3 for r in rows], [r[y] * 1e3 for r in rows], c=[r[T] for r in rows], s=4,
                    cmap="inferno")
    fig.colorbar(sc, label="T [K]")
    vtk = sorted(glob.glob("cutter-*.vtk"), key=lambda f: int(re.findall(r"\d+", f)[-1]))
    if vtk:
        for s in tool_segments(vtk[-1]):
            ax.plot([q[0] * 1e3 for q in s], [q[1] * 1e3 for q in s], "c-", lw=1)
        ax.set_title("step %d (particles), %s (cutter)" % (step, vtk[-1]), fontsize=9)
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    fig.tight_layout()
    fig.savefig("picture.png", dpi=130)


if __name__ == "__main__":
    main()
