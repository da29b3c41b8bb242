#!/usr/bin/env python3
"""The last frame of dump.fsw: the temperature on the plate's top surface (the particles within one
spacing of the highest ones at each x, y column, seen from +z) and in the cross-section across the
joint through the tool's axis (the particles within half a spacing of x = axis), the joint-line
particles (type 2) marked, into picture.png.  Run in the output folder; the axis x from fsw.params
is not needed: the section is taken through the hottest particle's x.
Usage: python3 picture.py [-i dump.fsw] [-o picture.png]"""
import argparse
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
from dump2vtu import last_frame  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("-i", default="dump.fsw")
ap.add_argument("-o", default="picture.png")
ap.add_argument("--dx", type=float, default=0.5e-3, help="particle spacing of the run (m)")
a = ap.parse_args()
step, cols, rows = last_frame(a.i)
if rows is None:
    sys.exit(f"picture.py: no frame in {a.i}")
c = {name: i for i, name in enumerate(cols)}
X, Y, Z, T, TY = (c["x"], c["y"], c["z"], c["temperature"], c["type"])
dx = a.dx
hot = max(rows, key=lambda r: r[T])
# the section through the centre of the hottest 2 % (about the tool's axis)
hs = sorted(rows, key=lambda r: -r[T])[:max(1, len(rows) // 50)]
xsec = sum(r[X] for r in hs) / len(hs)
top = {}
for r in rows:
    key = (round(r[X] / dx), round(r[Y] / dx))
    if key not in top or r[Z] > top[key][Z]:
        top[key] = r
fig, ax = plt.subplots(1, 2, figsize=(12, 4.5), gridspec_kw={"width_ratios": [1.4, 1]})
tp = list(top.values())
sc = ax[0].scatter([r[X] * 1e3 for r in tp], [r[Y] * 1e3 for r in tp], c=[r[T] for r in tp], s=6,
                   cmap="inferno", vmin=300, vmax=max(r[T] for r in rows))
jt = [r for r in tp if r[TY] == 2]
ax[0].scatter([r[X] * 1e3 for r in jt], [r[Y] * 1e3 for r in jt], s=1, c="c", label="joint line")
ax[0].set_aspect("equal")
ax[0].set_xlabel("x (mm, traverse)")
ax[0].set_ylabel("y (mm)")
ax[0].set_title("top surface, step %d" % step)
ax[0].legend(loc="upper right", fontsize=8)
sec = [r for r in rows if abs(r[X] - xsec) < 0.5 * dx]
ax[1].scatter([r[Y] * 1e3 for r in sec], [r[Z] * 1e3 for r in sec], c=[r[T] for r in sec], s=14,
              cmap="inferno", vmin=300, vmax=max(r[T] for r in rows))
ax[1].set_aspect("equal")
ax[1].set_xlabel("y (mm, across the joint)")
ax[1].set_ylabel("z (mm)")
ax[1].set_title("section x = %.2f mm (centre of the hottest 2 %%)" % (xsec * 1e3))
fig.colorbar(sc, ax=ax, label="temperature (K); solidus 855 K")
fig.savefig(a.o, dpi=110)
print("picture.py: step %d, %d particles, peak %.1f K at (%.2f, %.2f, %.2f) mm -> %s"
      % (step, len(rows), hot[T], hot[X] * 1e3, hot[Y] * 1e3, hot[Z] * 1e3, a.o))
