#!/usr/bin/env python3
"""Normal and shear stress and Usui wear rate along the rake face and the flank, against the
distance from the cutting edge: the tool fields of fix contact/tri-penalty (-var toolfields N
of the cutting examples), read from tool-fields.dat (fix ave/time mode vector: per interval a
line "step nrows", then one line per facet: index and the 15 columns of the fix's array).

The intervals after a fraction --skip of the run (default 0.5: the steady part of the cut) are
averaged per facet: stresses, contacts and wear rate as plain means of the intervals, sliding
speed and temperature weighted by the contacts; the wear depth is the last interval's.  The
distance of a facet from the cutting edge is that of its centroid from the mean centroid of the
edge facets (feature 2), in the x-y plane (2D: along the face, to within half a facet and the
edge radius; 3D: the two triangles of a strip give two points).  A rounded edge's own facets are
listed in the table as "edge", from the rake face's side (distance > 0) round to the flank's (< 0).

Facets with fewer contacts than --min-contacts (default 0.02, a time average) are not
plotted (listed in the table): a stray particle touching the far end of a face now and
then gives it a stress and speed of its own.

usage: tool_fields.py [tool-fields.dat] [--skip 0.5] [--min-contacts 0.02] [--out tool-fields.png]
"""
import argparse
import math
import sys

SN, TAU, VS, TEMP, NC, WEAR, DEPTH, FX, FY, FZ, AREA, FEAT, CX, CY, CZ = range(15)


def read_blocks(path):
    blocks, cur, step = [], None, None
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            v = [float(x) for x in line.split()]
            if len(v) == 2:
                cur = []
                step = int(v[0])
                blocks.append((step, cur))
            elif len(v) == 16 and cur is not None:
                cur.append(v[1:])
    return [b for b in blocks if b[1]]


def profiles(blocks, skip):
    # the first block (step 0, nothing averaged yet) and the first part of the run are left out
    use = [b for b in blocks[1:] if b[0] >= blocks[-1][0] * skip] or blocks[-1:]
    nf = len(use[-1][1])
    mean = [[0.0] * 15 for _ in range(nf)]
    for _, rows in use:
        for f, r in enumerate(rows):
            for c in (SN, TAU, NC, WEAR, FX, FY, FZ):
                mean[f][c] += r[c] / len(use)
            for c in (VS, TEMP):
                mean[f][c] += r[c] * r[NC]
    last = use[-1][1]
    for f in range(nf):
        for c in (VS, TEMP):
            mean[f][c] = mean[f][c] / (mean[f][NC] * len(use)) if mean[f][NC] > 0 else 0.0
        for c in (DEPTH, AREA, FEAT, CX, CY, CZ):
            mean[f][c] = last[f][c]
    edge = [r for r in mean if r[FEAT] == 2]
    if not edge:    # a sharp tool: the vertex shared by the rake face and the flank
        edge = [min((r for r in mean if r[FEAT] in (1, 3)), key=lambda r: r[CY])]
    ex = sum(r[CX] for r in edge) / len(edge)
    ey = sum(r[CY] for r in edge) / len(edge)
    out = {}
    for feat, name in ((1, "rake"), (3, "flank")):
        rows = sorted(([math.hypot(r[CX] - ex, r[CY] - ey)] + r for r in mean if r[FEAT] == feat))
        out[name] = rows
    # a rounded edge's own facets (table only): distance from the edge's mean centroid, > 0 on the
    # rake face's side (above it), < 0 on the flank's, from the rake face round to the flank
    rows = [[math.copysign(math.hypot(r[CX] - ex, r[CY] - ey), r[CY] - ey)] + r for r in mean if r[FEAT] == 2]
    return out, sorted(rows, key=lambda r: -r[0]), use


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file", nargs="?", default="tool-fields.dat")
    ap.add_argument("--skip", type=float, default=0.5, help="leave out the intervals before this fraction of the run")
    ap.add_argument("--min-contacts", type=float, default=0.02, help="plot only facets with at least this many contacts")
    ap.add_argument("--out", default="tool-fields.png")
    a = ap.parse_args()
    blocks = read_blocks(a.file)
    if len(blocks) < 2:
        sys.exit(f"{a.file}: no averaging interval after step 0 (run with -var toolfields N, N < the run's steps)")
    prof, edge, use = profiles(blocks, a.skip)
    print(f"# {len(use)} intervals, steps {use[0][0]}-{use[-1][0]}")
    print("# face  distance_um  sigma_n_MPa  tau_MPa  v_s_m/s  T_K  contacts  wear_rate_m/s  wear_depth_m")
    for name, rows in list(prof.items()) + [("edge", edge)]:
        for r in rows:
            d, v = r[0], r[1:]
            print(f"{name:5s} {d * 1e6:9.2f} {v[SN] / 1e6:10.2f} {v[TAU] / 1e6:9.2f} {v[VS]:8.3f} {v[TEMP]:7.1f} "
                  f"{v[NC]:8.3f} {v[WEAR]:12.4e} {v[DEPTH]:12.4e}")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("(no matplotlib: table only)")
        return
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    twins = []
    for ax, (name, rows) in zip(axes, prof.items()):
        dmax = max(r[0] for r in rows) * 1e6 if rows else 1.0
        rows = [r for r in rows if r[1 + NC] >= a.min_contacts]
        d = [r[0] * 1e6 for r in rows]
        ax.set_xlim(0.0, dmax)
        ax.plot(d, [r[1 + SN] / 1e6 for r in rows], "o-", label="normal stress")
        ax.plot(d, [r[1 + TAU] / 1e6 for r in rows], "s-", label="shear stress")
        ax.set_xlabel(f"distance from the cutting edge along the {name} [um]")
        ax.grid(alpha=0.3)
        ax2 = ax.twinx()
        twins.append(ax2)
        ax2.plot(d, [r[1 + WEAR] * 1e6 for r in rows], "^-", color="tab:red", label="Usui wear rate")
        ax2.set_ylabel("wear rate [um/s]", color="tab:red")
        ax2.set_ylim(bottom=0.0)
        ax.set_title(f"{name} face")
        if name == "rake":
            ax.set_ylabel("stress [MPa]")
            h1, l1 = ax.get_legend_handles_labels()
            h2, l2 = ax2.get_legend_handles_labels()
            ax.legend(h1 + h2, l1 + l2, loc="upper right", fontsize=8)
    axes[0].set_ylim(bottom=0.0)
    top = max(t.get_ylim()[1] for t in twins)    # one wear-rate scale for both faces
    for t in twins:
        t.set_ylim(0.0, top)
    fig.suptitle(f"tool loads and wear, steps {use[0][0]}-{use[-1][0]} ({len(use)} intervals)")
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)
    print(f"plot: {a.out}")


if __name__ == "__main__":
    main()
