#!/usr/bin/env python3
"""Milling example: force on the cutter against the cutter angle, beside the mechanistic model.

Reads milling.dat (in.milling) in the current folder, writes milling.png and prints the peak and
mean forces of the simulation and the model over the angles run.  Usage:
  python3 plot.py [milling.dat] [--R 1e-3 --teeth 2 --fz 0.08e-3 --ae 0.5e-3 --mode up --vc 70]
(default: the values of milling.params, which in.milling writes beside milling.dat, else in.milling's
defaults; an option given here wins).

Angle convention (Altintas, "Manufacturing Automation", ch. 2): the cutter turns clockwise seen
from +z, the feed is +x, phi is a tooth's angle clockwise from +y; the uncut chip thickness is
h(phi) = fz sin(phi) inside the engagement (up-milling: 0 <= phi <= arccos(1 - ae/R); down-milling:
180 - arccos(1 - ae/R) <= phi <= 180), else 0.  Per unit width b (2D: per mm):
  F_t = Kc b h + Ke b   (tangential: against the tooth's motion)
  F_r = Kr b h + Kre b  (radial: pushes the tooth towards the axis)
and the force on the cutter, summed over the teeth in the cut,
  Fx = -F_t cos(phi) - F_r sin(phi),  Fy = F_t sin(phi) - F_r cos(phi),  torque = R F_t.
Kc, Ke, Kr, Kre are the per-speed fits F = F0 + k h of the measured orthogonal Ti6Al4V forces of
bench/validation (results/seed003/table.md, "Edge and chip"; Klippel et al. 2024's dataset):
Kc = kc, Ke = Fc0, Kr = kt, Kre = Ft0; the speed nearest vc is taken."""
import argparse
import math

# vc (m/min): Fc0 (N/mm), kc (N/mm per mm), Ft0 (N/mm), kt (N/mm per mm), measured
FITS = {19.9: (44.0, 1640.0, 79.0, 626.0), 70.0: (51.0, 1460.0, 90.0, 457.0), 100.0: (48.0, 1450.0, 88.0, 456.0)}


def coefficients(vc):
    v = min(FITS, key=lambda s: abs(s - vc))
    Fc0, kc, Ft0, kt = FITS[v]
    return v, dict(Kc=kc, Ke=Fc0, Kr=kt, Kre=Ft0)


def engagement(R, ae, mode):
    a = math.degrees(math.acos(1.0 - ae / R))
    return (0.0, a) if mode == "up" else (180.0 - a, 180.0)


def model(phi_deg, R, teeth, fz, ae, mode, K):
    """Force on the cutter (N/mm) and torque (N m per mm) at tooth 0's angle phi (deg)."""
    st, ex = engagement(R, ae, mode)
    fx = fy = tq = 0.0
    for j in range(teeth):
        p = (phi_deg + 360.0 * j / teeth) % 360.0
        if not st <= p <= ex:
            continue
        h = fz * 1e3 * math.sin(math.radians(p))                # mm
        ft = K["Kc"] * h + K["Ke"]                              # N/mm
        fr = K["Kr"] * h + K["Kre"]
        c, s = math.cos(math.radians(p)), math.sin(math.radians(p))
        fx += -ft * c - fr * s
        fy += ft * s - fr * c
        tq += R * ft                                            # N m per mm
    return fx, fy, tq


def read(path):
    rows = []
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            v = [float(x) for x in line.split()]
            if v[0] > 0:                                        # step 0: the tool fields are not set yet
                rows.append(v)
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("data", nargs="?", default="milling.dat")
    ap.add_argument("--R", type=float, default=1e-3)
    ap.add_argument("--teeth", type=int, default=2)
    ap.add_argument("--fz", type=float, default=0.08e-3)
    ap.add_argument("--ae", type=float, default=0.5e-3)
    ap.add_argument("--mode", default="up", choices=("up", "down"))
    ap.add_argument("--vc", type=float, default=70.0)
    ap.add_argument("-o", "--out", default="milling.png")
    # the values the run used (in.milling writes milling.params beside milling.dat) unless given here
    import os
    params = os.path.join(os.path.dirname(os.path.abspath(ap.parse_args().data)), "milling.params")
    if os.path.exists(params):
        t = open(params).read().split()
        kv = dict(zip(t[0::2], t[1::2]))
        ap.set_defaults(**{k: (float(v) if k in ("R", "fz", "ae", "vc") else int(v) if k == "teeth" else v)
                           for k, v in kv.items() if k in ("R", "teeth", "fz", "ae", "mode", "vc")})
    o = ap.parse_args()
    v, K = coefficients(o.vc)
    rows = read(o.data)
    phi = [r[3] for r in rows]                                  # phi_rate (unwrapped)
    sim = {"Fx": [r[4] for r in rows], "Fy": [r[5] for r in rows], "torque": [r[6] for r in rows]}
    mod = [model(p, o.R, o.teeth, o.fz, o.ae, o.mode, K) for p in phi]
    mdl = {"Fx": [m[0] for m in mod], "Fy": [m[1] for m in mod], "torque": [m[2] for m in mod]}
    st, ex = engagement(o.R, o.ae, o.mode)
    print("coefficients at %g m/min (nearest to vc %g): Kc %g N/mm^2, Ke %g N/mm, Kr %g N/mm^2, Kre %g N/mm"
          % (v, o.vc, K["Kc"], K["Ke"], K["Kr"], K["Kre"]))
    print("phi %.1f..%.1f deg (engagement of a tooth %.1f..%.1f), %d rows" % (phi[0], phi[-1], st, ex, len(rows)))
    for k in ("Fx", "Fy", "torque"):
        s, m = sim[k], mdl[k]
        print("%-6s sim: mean %9.4g min %9.4g max %9.4g | model: mean %9.4g min %9.4g max %9.4g"
              % (k, sum(s) / len(s), min(s), max(s), sum(m) / len(m), min(m), max(m)))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("no matplotlib: no plot")
        return
    fig, ax = plt.subplots(2, 1, figsize=(7, 7), sharex=True)
    for k, c in (("Fx", "C0"), ("Fy", "C1")):
        ax[0].plot(phi, sim[k], c, lw=0.8, label=k + " sphcut")
        ax[0].plot(phi, mdl[k], c + "--", lw=1.5, label=k + " model")
    ax[0].set_ylabel("force on the cutter [N/mm]")
    ax[0].legend(fontsize=8)
    ax[0].axhline(0, color="k", lw=0.5)
    ax[1].plot(phi, [1e3 * x for x in sim["torque"]], "C2", lw=0.8, label="torque sphcut")
    ax[1].plot(phi, [1e3 * x for x in mdl["torque"]], "C2--", lw=1.5, label="torque model R F_t")
    ax[1].set_ylabel("spindle torque [N mm/mm]")
    ax[1].set_xlabel("tooth 0 angle phi [deg, clockwise from +y]")
    ax[1].legend(fontsize=8)
    fig.suptitle("2D %s-milling, %d teeth, R %g mm, fz %g mm, ae %g mm; model: fits at %g m/min"
                 % (o.mode, o.teeth, o.R * 1e3, o.fz * 1e3, o.ae * 1e3, v), fontsize=9)
    fig.tight_layout()
    fig.savefig(o.out, dpi=120)
    print("wrote", o.out)


if __name__ == "__main__":
    main()
