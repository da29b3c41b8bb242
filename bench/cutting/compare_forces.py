#!/usr/bin/env python3
"""Forces of several cutting runs against the cut length, one panel for Fc and one for Ft (running
means over MEAN mm), with the experiment (dashed) and the paper's SPH (dotted): a resolution or
CPU-vs-GPU comparison.  Also prints each run's steady means over [LO, HI] mm of cut.
Usage: compare_forces.py OUT.png LABEL=forces.dat [LABEL=forces.dat ...] [--window LO HI] [--mean MM]
(python from tools/python-deps.sh --print-python; forces.dat as written by the cutting examples)."""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "../../examples/cutting-2d-ti6al4v"))
from steady import read_rows    # noqa: E402
from seed003 import EXP_FC, EXP_FT, SPH_FC, SPH_FT    # noqa: E402


def main(argv):
    lo, hi, mean = 0.2, None, 0.05
    if "--window" in argv:
        k = argv.index("--window")
        lo, hi = float(argv[k + 1]), float(argv[k + 2])
        del argv[k:k + 3]
    if "--mean" in argv:
        k = argv.index("--mean")
        mean = float(argv[k + 1])
        del argv[k:k + 2]
    png, runs = argv[0], [a.split("=", 1) for a in argv[1:]]
    fig, axes = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    for label, path in runs:
        a = np.array(read_rows(path))
        l, fc, ft = a[:, 1], a[:, 2], a[:, 3]    # read_rows: time, cut [mm], Fc, Ft, ...
        top = hi if hi is not None else l.max()
        sel = (l >= lo) & (l <= top)
        print(f"{label:20s} {path}: steady over {lo:.2f}-{top:.2f} mm: Fc {fc[sel].mean():.1f} N/mm, "
              f"Ft {ft[sel].mean():.1f} N/mm ({sel.sum()} samples)")
        # running mean over `mean` mm of cut (samples are evenly spaced in time, hence in cut length)
        n = max(1, int(round(mean / max(np.median(np.diff(l[l > 0])), 1e-12))))
        kern = np.ones(n) / n
        for ax, y in zip(axes, (fc, ft)):
            ax.plot(l[n - 1:], np.convolve(y, kern, mode="valid"), lw=1, label=label)
    for ax, e, s, name in zip(axes, (EXP_FC, EXP_FT), (SPH_FC, SPH_FT), ("Fc", "Ft")):
        ax.axhline(e, ls="--", c="k", lw=1, label="experiment")
        ax.axhline(s, ls=":", c="k", lw=1, label="paper's SPH, mu 0.35")
        ax.set_ylabel(f"{name} [N/mm]")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, ncol=2)
    axes[1].set_xlabel("cut length [mm]")
    fig.tight_layout()
    fig.savefig(png, dpi=110)


if __name__ == "__main__":
    main(sys.argv[1:])
