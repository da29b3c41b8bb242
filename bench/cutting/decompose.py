#!/usr/bin/env python3
"""Decomposition of the steady cutting forces of examples/cutting-2d-ti6al4v runs made with
-var decomp N (fix contact/tri-penalty global vector 16-39, written to decomp.dat): Fc and Ft
of the rake face, the cutting edge and the flank, each split into its normal and friction
parts; contacts, sum |F_T| / sum F_N and the fraction of contacts at the Coulomb limit per
feature.  With a dump holding fcontact_n, fcontact_t, contact_feature (the example's dump does),
also the distribution of |F_T|/F_N over the rake-face contact particles.
Means over the frames after 10 % of the cut, as examples/cutting-2d-ti6al4v/steady.py.
With DX (the particle spacing), also the temperature, plastic strain rate and plastic strain
of the first particle layers at the rake face against the chip further away.
Usage: decompose.py RUN_DIR [MU [DX]]    (MU: the run's friction coefficient, default 0.35)
       decompose.py --table DX RUN[:MU] ...   (one markdown row per run)"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "examples", "cutting-2d-ti6al4v"))
from seed003 import STEADY_FROM, block_error, steady_rows  # noqa: E402
from steady import read_rows  # noqa: E402

FEATURES = ("rake", "edge", "flank")


def steady_forces(run):
    lmax, sel = steady_rows(read_rows(os.path.join(run, "forces.dat")))
    return lmax, sum(r[2] for r in sel) / len(sel), sum(r[3] for r in sel) / len(sel), \
        sum(r[5] for r in sel) / len(sel), len(sel)


def steady_errors(run):
    sel = steady_rows(read_rows(os.path.join(run, "forces.dat")))[1]
    return block_error([r[2] for r in sel]), block_error([r[3] for r in sel])


def decomposition(run):
    """mean of each decomp.dat column over the steady frames: per feature normal x y,
    friction x y (N/m on the tool), contacts, sum F_N, sum |F_T|, contacts at the limit"""
    by_step = {}
    for line in open(os.path.join(run, "decomp.dat")):
        if line.startswith("#") or not line.strip():
            continue
        v = line.split()
        by_step[int(v[0])] = [float(x) for x in v[1:]]
    rows = [by_step[k] for k in sorted(by_step)]
    lmax = max(r[0] for r in rows)
    sel = [r for r in rows if r[0] >= STEADY_FROM * lmax and r[0] > 0.0]
    ncol = len(sel[0]) - 1
    return [sum(r[1 + c] for r in sel) / len(sel) for c in range(ncol)], len(sel)


def frames(run):
    """the dump frames (list of dicts column -> list of values) that have rake-face contacts,
    without the first 10 % of them (the tool reaches the workpiece after the first frames)"""
    path = os.path.join(run, "dump.cutting")
    if not os.path.exists(path):
        return []
    lines = open(path).read().split("\n")
    k, n, out = 0, 0, []
    while k < len(lines):
        if lines[k].startswith("ITEM: NUMBER OF ATOMS"):
            n = int(lines[k + 1])
            k += 2
        elif lines[k].startswith("ITEM: ATOMS"):
            cols = lines[k].split()[2:]
            if "contact_feature" not in cols:
                return []
            rows = [[float(x) for x in line.split()] for line in lines[k + 1:k + 1 + n]]
            out.append({c: [r[j] for r in rows] for j, c in enumerate(cols)})
            k += 1 + n
        else:
            k += 1
    withc = [f for f in out if 1.0 in f["contact_feature"]]
    return withc[max(1, len(withc) // 10):] if len(withc) > 1 else withc


def distribution(fr):
    """|F_T|/F_N of the rake-face contacts (F_N > 0)"""
    ratios = []
    for f in fr:
        for fe, fn, ft in zip(f["contact_feature"], f["fcontact_n"], f["fcontact_t"]):
            if fe == 1.0 and fn > 0.0:
                ratios.append(ft / fn)
    return ratios


def layers(fr, dx):
    """mean temperature, plastic strain rate and plastic strain of the rake-face contact
    particles (layer 1) and of the workpiece particles 1 and 2 spacings further from the rake
    face (layers 2, 3: x within dx/2 of x_1 - dx, x_1 - 2 dx, x_1 the mean x of layer 1, and y
    within the contact particles' y range) and 4.5-6.5 spacings away (layer 5)"""
    acc = {1: [], 2: [], 3: [], 5: []}
    for f in fr:
        idx = [i for i, fe in enumerate(f["contact_feature"]) if fe == 1.0]
        x1 = sum(f["x"][i] for i in idx) / len(idx)
        ylo, yhi = min(f["y"][i] for i in idx), max(f["y"][i] for i in idx)
        for i in idx:
            acc[1].append(i_vals(f, i))
        for i in range(len(f["x"])):
            if f["role"][i] != 0.0 or f["contact_feature"][i] != 0.0 or not ylo <= f["y"][i] <= yhi:
                continue
            d = (x1 - f["x"][i]) / dx
            for lay, (lo, hi) in ((2, (0.5, 1.5)), (3, (1.5, 2.5)), (5, (4.5, 6.5))):
                if lo <= d < hi:
                    acc[lay].append(i_vals(f, i))
    return {lay: [sum(v[c] for v in vals) / len(vals) for c in range(3)] + [len(vals) / max(1, len(fr))]
            for lay, vals in acc.items() if vals}


def i_vals(f, i):
    return (f["temperature"][i], f["plastic_strain_rate"][i], f["plastic_strain"][i])


def main(run, mu=0.35, dx=0.0):
    lmax, fc, ft, trake, ns = steady_forces(run)
    d, nd = decomposition(run)
    print(f"{run}: steady state over {STEADY_FROM * lmax:.3f}-{lmax:.3f} mm ({ns} force samples, {nd} decomposition samples)")
    print(f"total (forces.dat): Fc {fc:.1f} N/mm, Ft {ft:.1f} N/mm, Ft/Fc {ft / fc:.3f}, T_rake {trake:.0f} K")
    print(f"{'feature':8s} {'Fc_N':>7s} {'Fc_fric':>8s} {'Ft_N':>7s} {'Ft_fric':>8s} {'sumFN':>7s} {'sum|FT|':>8s} "
          f"{'contacts':>8s} {'sum|FT|/sumFN':>13s} {'at limit':>8s}   (N/mm; on the tool)")
    sfc = sft = 0.0
    for f, name in enumerate(FEATURES):
        b = 8 * f
        nx, ny, tx, ty, nc, sfn, sft_, nsl = d[b:b + 8]
        sfc += nx + tx
        sft += ny + ty
        ratio = sft_ / sfn if sfn > 0 else float("nan")
        frac = nsl / nc if nc > 0 else float("nan")
        print(f"{name:8s} {nx / 1e3:7.1f} {tx / 1e3:8.1f} {ny / 1e3:7.1f} {ty / 1e3:8.1f} {sfn / 1e3:7.1f} "
              f"{sft_ / 1e3:8.1f} {nc:8.2f} {ratio:13.3f} "
              f"{100 * frac:7.0f}%")
    print(f"{'sum':8s} Fc {sfc / 1e3:.1f} N/mm, Ft {sft / 1e3:.1f} N/mm (decomposition samples)")
    fr = frames(run)
    if fr:
        r, nf = distribution(fr), len(fr)
        if r:
            r.sort()
            q = lambda p: r[min(len(r) - 1, int(p * len(r)))]
            bins = [0.0, 0.25, 0.5, 0.75, 0.99, 1.01, 1e9]
            counts = [sum(1 for x in r if bins[j] * mu <= x < bins[j + 1] * mu) for j in range(len(bins) - 1)]
            print(f"rake-face |F_T|/F_N over {len(r)} contact particles in {nf} dump frames: "
                  f"median {q(0.5):.3f}, quartiles {q(0.25):.3f} / {q(0.75):.3f}, mean {sum(r) / len(r):.3f} (mu {mu})")
            labels = ["<0.25mu", "0.25-0.5mu", "0.5-0.75mu", "0.75-0.99mu", "at mu", ">mu"]
            print("  " + ", ".join(f"{l} {100 * c / len(r):.0f}%" for l, c in zip(labels, counts)))
        if dx > 0:
            print("interface layers (rake face; 1 = contact particles, 2, 3 = 1 and 2 spacings further, "
                  "5 = 4.5-6.5 spacings in front of the rake face):")
            for lay, (t, rate, eps, n) in sorted(layers(fr, dx).items()):
                print(f"  layer {lay}: T {t:6.0f} K, plastic strain rate {rate:9.3g} 1/s, plastic strain {eps:6.2f} "
                      f"({n:.1f} particles per frame)")


def loop_time(run):
    """loop time [s] and steps of the run's log (all run commands)"""
    import re
    t, n = 0.0, 0
    for m in re.finditer(r"Loop time of ([0-9.e+-]+) on \d+ procs for (\d+) steps", open(os.path.join(run, "log.cutting")).read()):
        t += float(m.group(1))
        n += int(m.group(2))
    return t, n


def table(dx, runs):
    """one markdown row per run (RUN or RUN:MU): the forces, the rake face's share and state,
    the contact layer's temperature"""
    print("| run | Fc [N/mm] (+- block error) | Ft [N/mm] | Ft/Fc | rake: F_N, friction Ft | edge + flank Ft | rake sum abs(F_T)/sum F_N, "
          "at mu | T contact layer / 2 spacings in [K] | steps |")
    print("|---|---|---|---|---|---|---|---|---|")
    for arg in runs:
        run, mu = (arg.split(":") + ["0.35"])[:2]
        lmax, fc, ft, trake, ns = steady_forces(run)
        d, nd = decomposition(run)
        rake, edge, flank = d[0:8], d[8:16], d[16:24]
        lay = layers(frames(run), dx) if dx > 0 else {}
        tl = f"{lay[1][0]:.0f} / {lay[3][0]:.0f}" if 1 in lay and 3 in lay else "-"
        n = loop_time(run)[1]
        ratio = rake[6] / rake[5] if rake[5] > 0 else float("nan")
        lim = rake[7] / rake[4] if rake[4] > 0 else float("nan")
        efc, eft = steady_errors(run)
        print(f"| {os.path.basename(run.rstrip('/'))} | {fc:.1f} +- {efc:.1f} | {ft:.1f} +- {eft:.1f} | {ft / fc:.2f} | {rake[0] / 1e3:.1f}, "
              f"{rake[3] / 1e3:.1f} | {(edge[1] + edge[3] + flank[1] + flank[3]) / 1e3:.1f} | {ratio:.3f}, "
              f"{100 * lim:.0f} % | {tl} | {n} |")


if __name__ == "__main__":
    if len(sys.argv) < 2 or (sys.argv[1] == "--table" and len(sys.argv) < 4):
        sys.exit(__doc__.split("Usage: ")[1])
    if sys.argv[1] == "--table":
        table(float(sys.argv[2]), sys.argv[3:])
        sys.exit(0)
    main(sys.argv[1], float(sys.argv[2]) if len(sys.argv) > 2 else 0.35,
         float(sys.argv[3]) if len(sys.argv) > 3 else 0.0)
