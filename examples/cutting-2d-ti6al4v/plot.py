#!/usr/bin/env python3
"""Orthogonal cutting example: forces.png (Fc, Ft per mm width against the cut length, with
the experiment and the paper's SPH values drawn) and temperature.png (the last dump frame
coloured by temperature).  Reads forces.dat and dump.cutting in the current folder."""
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from seed003 import EXP_FC, EXP_FT, SPH_FC, SPH_FT    # N/mm: experiment, the paper's SPH (mu 0.35)


def read_forces(path="forces.dat"):
    from steady import read_rows
    a = np.array(read_rows(path))
    return a[:, 0], a[:, 1], a[:, 2], a[:, 3], a[:, 4]    # time, lcut [mm], Fc, Ft [N/mm], Tmax


def last_frame(path="dump.cutting"):
    lines = open(path).read().splitlines()
    starts = [k for k, l in enumerate(lines) if l.startswith("ITEM: TIMESTEP")]
    k = starts[-1]
    step = int(lines[k + 1])
    n = int(lines[k + 3])
    cols = lines[k + 8].split()[2:]
    data = np.array([[float(v) for v in l.split()] for l in lines[k + 9:k + 9 + n]])
    return step, dict(zip(cols, data.T))


def main():
    t, lcut, fc, ft, tmax = read_forces()
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(lcut, fc, label="Fc sphcut", color="tab:blue")
    ax.plot(lcut, ft, label="Ft sphcut", color="tab:red")
    ax.axhline(EXP_FC, color="tab:blue", ls="--", lw=1, label="Fc experiment")
    ax.axhline(EXP_FT, color="tab:red", ls="--", lw=1, label="Ft experiment")
    ax.axhline(SPH_FC, color="tab:blue", ls=":", lw=1, label="Fc SPH (paper)")
    ax.axhline(SPH_FT, color="tab:red", ls=":", lw=1, label="Ft SPH (paper)")
    ax.set_xlabel("cut length [mm]")
    ax.set_ylabel("force per width [N/mm]")
    ax.legend(fontsize=8, ncol=3)
    ax.set_ylim(bottom=0)
    fig.tight_layout()
    fig.savefig("forces.png", dpi=120)
    try:
        step, d = last_frame()
    except (OSError, IndexError):
        return
    fig, ax = plt.subplots(figsize=(7, 4))
    work = d["type"] == 1
    sc = ax.scatter(d["x"][work] * 1e3, d["y"][work] * 1e3, c=d["temperature"][work], s=4, cmap="inferno")
    ax.scatter(d["x"][~work] * 1e3, d["y"][~work] * 1e3, c=d["temperature"][~work], s=4, cmap="inferno",
               marker="s", vmin=sc.get_clim()[0], vmax=sc.get_clim()[1])
    fig.colorbar(sc, label="temperature [K]")
    ax.set_aspect("equal")
    if (~work).any():    # zoom on the cutting zone around the tool
        xt = d["x"][~work].min() * 1e3
        ax.set_xlim(xt - 0.6, xt + 0.35)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_title(f"step {step}")
    fig.tight_layout()
    fig.savefig("temperature.png", dpi=120)


if __name__ == "__main__":
    sys.exit(main())
