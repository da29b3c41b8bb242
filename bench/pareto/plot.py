#!/usr/bin/env python3
"""bench/pareto: error against wall time (log-log), one panel per reference, one colour per
option, points labelled with the resolution.  Reads results.csv of run.sh (measured: filled
markers) and recorded.csv (figures of earlier runs, NOT rerun: hollow markers; GPU runs as
squares).  The marker shape says where the wall time was taken.
Usage: plot.py results.csv recorded.csv pareto.png"""
import csv
import math
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.lines import Line2D
from matplotlib.ticker import FuncFormatter

PANELS = [
    ("plate", None, "oscillating plate: |period error| vs beam theory [%]", "particles across"),
    ("conduction", None, "conduction: max error / amplitude [%]", "n x n"),
    ("taylor", None, "Taylor bar: |final length error| vs 21.47 mm [%]", "dx"),
    ("cut", "experiment", "2D cut: |force error| vs experiment [%]", "particles across"),
    ("cut", "finest", "2D cut: |force error| vs the finest run [%]", "particles across"),
]
COLOURS = {"cubic": "C0", "wendland": "C1", "fmfs": "C0", "brookshaw": "C1",
           "Fc vs experiment": "C0", "Ft vs experiment": "C3",
           "Fc vs experiment (old contact)": "C2", "Ft vs experiment (old contact)": "C1",
           "Fc vs finest": "C0", "Ft vs finest": "C3",
           "Fc vs finest (old contact)": "C2", "Ft vs finest (old contact)": "C1"}


def platform_marker(p):
    if p.startswith("H100"):
        return "s"
    if p.startswith("1 core"):
        return "o"
    if p.startswith("2 ranks"):
        return "D"
    return "^"      # 8 or 16 ranks of the 16-core Xeon


def read(path, recorded):
    rows = list(csv.DictReader(line for line in open(path) if not line.startswith("#")))
    for r in rows:
        r["recorded"] = recorded
    return rows


def main(results, recorded, png):
    rows = read(results, False) + read(recorded, True)
    fig, axes = plt.subplots(2, 3, figsize=(15, 8.6))
    axes = axes.ravel()
    for ax, (case, sub, ylabel, reslabel) in zip(axes, PANELS):
        sel = [r for r in rows if r["case"] == case and (sub is None or sub in r["option"])]
        # one line per option and platform (a line never joins different machines)
        groups = {}
        for r in sel:
            groups.setdefault((r["option"], r["platform"], r["recorded"]), []).append(r)
        labelled = set()
        for (opt, plat, rec), rs in sorted(groups.items()):
            pts = sorted((float(r["wall_s"]), abs(float(r["error_pct"])), r["resolution"],
                          "est." in r["platform"] or "est." in r.get("note", "")) for r in rs)
            col = COLOURS.get(opt, "k")
            mk = platform_marker(plat)
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "-" if len(pts) > 1 else "",
                    color=col, alpha=0.6)
            for t, e, res, est in pts:
                ax.plot([t], [e], mk, color=col, markersize=7,
                        markerfacecolor="none" if rec else col, linestyle="")
                ax.annotate(res + (" (est. time)" if est else ""), (t, e), textcoords="offset points",
                            xytext=(4, 4), fontsize=7)
            if opt not in labelled:
                ax.plot([], [], "-", color=col, label=opt)
                labelled.add(opt)
        if case in ("taylor", "cut"):
            for lvl in (2, 5, 10):
                ax.axhline(lvl, color="grey", lw=0.6, ls=":")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        ax.yaxis.set_minor_formatter(FuncFormatter(
            lambda v, _: f"{v:g}" if v > 0 and round(v / 10 ** math.floor(math.log10(v))) in (2, 3, 5) else ""))
        ax.set_xlabel("wall time of the run [s] (marker: where)")
        ax.set_ylabel(ylabel, fontsize=8)
        ax.set_title(f"{case} (labels: {reslabel})", fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    # the last cell: the key to the markers
    key = axes[-1]
    key.axis("off")
    handles = [Line2D([], [], marker="o", color="k", ls="", label="1 core, this 2-core VM (measured)"),
               Line2D([], [], marker="D", color="k", ls="", label="2 MPI ranks, this VM"),
               Line2D([], [], marker="^", color="k", ls="", markerfacecolor="none",
                      label="8 / 16 MPI ranks, 16-core Xeon (recorded)"),
               Line2D([], [], marker="s", color="k", ls="", markerfacecolor="none",
                      label="one H100 GPU (recorded)"),
               Line2D([], [], marker="o", color="k", ls="", markerfacecolor="none",
                      label="hollow: recorded.csv, not rerun by run.sh"),
               Line2D([], [], color="grey", ls=":", label="2 %, 5 %, 10 %")]
    key.legend(handles=handles, loc="center", fontsize=9, title="markers")
    key.text(0.0, 0.02, "cut: 2 mm of cut unless labelled; 'old contact' = before the contact\n"
             "spring limited dt (fewer steps, lower forces); Ft is ~50 % low at\n"
             "every resolution (model, issue 13), not a resolution effect",
             fontsize=8, transform=key.transAxes)
    fig.tight_layout()
    fig.savefig(png, dpi=100)
    print(f"wrote {png}")
    for r in rows:
        print(",".join(r[k] for k in ["case", "option", "resolution", "particles", "steps", "wall_s",
                                      "error_pct", "platform"]) + (",recorded" if r["recorded"] else ""))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3])
