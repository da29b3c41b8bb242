#!/usr/bin/env python3
"""Plot fsw.dat (examples/fsw-3d-aluminium): axial force Fz, traverse force Fx, spindle torque and
power, peak temperature against time, the phases (1 plunge, 2 dwell, 3 traverse) shaded.
Usage: python3 plot.py [-i fsw.dat] [-o fsw.png]"""
import argparse

ap = argparse.ArgumentParser()
ap.add_argument("-i", default="fsw.dat")
ap.add_argument("-o", default="fsw.png")
a = ap.parse_args()
rows = [[float(x) for x in l.split()] for l in open(a.i) if l.strip() and not l.startswith("#")]
t = [r[1] * 1e3 for r in rows]
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
fig, ax = plt.subplots(4, 1, figsize=(7, 9), sharex=True)
ax[0].plot(t, [r[6] / 1e3 for r in rows], label="Fz (axial)")
ax[0].plot(t, [r[7] / 1e3 for r in rows], label="Fx (traverse)")
ax[0].set_ylabel("force on the tool (kN)")
ax[0].legend()
ax[1].plot(t, [r[8] for r in rows])
ax[1].set_ylabel("torque (N m)")
ax[2].plot(t, [r[9] / 1e3 for r in rows])
ax[2].set_ylabel("spindle power (kW)")
ax[3].plot(t, [r[11] for r in rows], label="peak, workpiece")
ax[3].axhline(855, color="r", ls="--", label="solidus 855 K (JC Tmelt)")
ax[3].set_ylabel("temperature (K)")
ax[3].set_xlabel("time (ms; time-compressed process, README)")
ax[3].legend()
for axi in ax:
    for ph, c in ((2, "0.9"), (3, "0.8")):
        ts = [r[1] * 1e3 for r in rows if r[2] == ph]
        if ts:
            axi.axvspan(min(ts), max(ts), color=c, zorder=0)
fig.tight_layout()
fig.savefig(a.o, dpi=110)
print("plot.py: %d rows, last t %.3f ms, peak T %.1f K -> %s" % (len(rows), t[-1], max(r[11] for r in rows), a.o))
