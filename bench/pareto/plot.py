#!/usr/bin/env python3
"""bench/pareto: error against wall time (log-log), one panel per reference, one line per
option, points labelled with the resolution.  Reads results.csv of run.sh.
Usage: plot.py results.csv pareto.png"""
import csv
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

PANELS = [("plate", "oscillating plate: |period error| vs beam theory [%]", "particles across"),
          ("conduction", "conduction: max error / amplitude [%]", "n x n")]


def main(path, png):
    rows = list(csv.DictReader(open(path)))
    fig, axes = plt.subplots(1, len(PANELS), figsize=(11, 4.2))
    for ax, (case, ylabel, reslabel) in zip(axes, PANELS):
        sel = [r for r in rows if r["case"] == case]
        for opt in sorted({r["option"] for r in sel}):
            pts = sorted((float(r["wall_s"]), abs(float(r["error_pct"])), r["resolution"])
                         for r in sel if r["option"] == opt)
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", label=opt)
            for t, e, res in pts:
                ax.annotate(res, (t, e), textcoords="offset points", xytext=(4, 4), fontsize=8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall time of the run, 1 core [s]")
        ax.set_ylabel(ylabel)
        ax.set_title(f"{case} (labels: {reslabel})")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    print(f"wrote {png}")
    for r in rows:
        print(",".join(r[k] for k in ["case", "option", "resolution", "particles", "steps", "wall_s", "error_pct"]))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
