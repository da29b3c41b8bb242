#!/usr/bin/env python3
"""Odd-even (hourglass, zero-energy) indicator of the velocity field of examples/cutting-2d-ti6al4v
runs, from their dump (x y vx vy density role contact_feature ...; the example's dump has them).

Per dump frame, for every SPH particle of the workpiece (role 0 and 2), with the kernel of the run
(cubic B-spline, h = HDX dx, default 1.3) and V_j = m / rho_j (m = 4430 dx^2):
  L_i   the renormalised velocity gradient, as pair sph/jc-thermal computes it,
  e_ij  = (v_j - v_i) - 1/2 (L_i + L_j)(x_j - x_i): the part of a pair's velocity difference that
          the two particles' velocity gradients do not predict (what `hourglass` damps; 0 for a
          linear field, O(1) for an odd-even mode, O(h^2 |grad grad v|) for a smooth field),
  eta_i = sqrt(sum_j W_ij |e_ij|^2 / sum_j W_ij), and lin_i the same of the predicted part,
  d_i   = v_i - sum_j W_ij V_j (v_j + L_j (x_i - x_j)) / sum_j W_ij V_j: the particle's velocity
          against what its neighbours' linear fields predict for it,
  C     = sum d_i . d_j / sum |d_i| |d_j| over the nearest-neighbour pairs (r < 1.2 dx) of the
          particles of a region: -1 for a perfect checkerboard, +1 for a smooth (curvature)
          residual, about 0 for noise or an odd-even mode along one lattice direction only.
  share = 1 - sum eq(L of v - d) / sum eq(L of v) over a region: the part of the von Mises
          equivalent strain rate (of the renormalised L) that goes with the residual d (what
          the odd-even part of the field adds to the strain rate the particles see).
Regions: the rake-face contact layer (contact_feature 1) and the layers 1, 2 and 4.5-6.5 spacings
further (as decompose.py), and all workpiece particles that move (|v| > 1 % of vc).
Prints per region the means over the frames after 10 % of the cut: eta / vc, sqrt(sum eta^2 /
sum lin^2) (the unpredicted part against the predicted one), C, share; then eta / vc of the contact
layer and of the moving material against the cut length (growth).
Usage: hourglass.py RUN_DIR NY [VC_M_PER_MIN [HDX]]
       hourglass.py --table NY RUN ...   (one markdown row per run)"""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples", "cutting-2d-ti6al4v"))
from seed003 import RHO0, STEADY_FROM, VC, spacing  # noqa: E402


def read_frames(path):
    """all frames of a dump: (step, dict column -> list)"""
    lines = open(path).read().split("\n")
    k, n, step, out = 0, 0, 0, []
    while k < len(lines):
        if lines[k].startswith("ITEM: TIMESTEP"):
            step = int(lines[k + 1])
            k += 2
        elif lines[k].startswith("ITEM: NUMBER OF ATOMS"):
            n = int(lines[k + 1])
            k += 2
        elif lines[k].startswith("ITEM: ATOMS"):
            cols = lines[k].split()[2:]
            rows = [[float(x) for x in line.split()] for line in lines[k + 1:k + 1 + n]]
            out.append((step, {c: [r[j] for r in rows] for j, c in enumerate(cols)}))
            k += 1 + n
        else:
            k += 1
    return out


def cubic(r, h):
    """W and (dW/dr)/r of the 2d cubic B-spline (support 2h)"""
    q = r / h
    s = 10.0 / (7.0 * math.pi * h * h)
    if q < 1.0:
        return s * (1.0 - 1.5 * q * q + 0.75 * q ** 3), s * (-3.0 * q + 2.25 * q * q) / (h * r) if r > 0 else 0.0
    if q < 2.0:
        return s * 0.25 * (2.0 - q) ** 3, s * (-0.75 * (2.0 - q) ** 2) / (h * r)
    return 0.0, 0.0


def analyse(f, dx, hdx, vc):
    """per particle (workpiece and clamped): eta, lin, d (2-vector), and the neighbour pairs"""
    h = hdx * dx
    idx = [i for i, r in enumerate(f["role"]) if r != 1.0]
    x, y, vx, vy, rho = (f[c] for c in ("x", "y", "vx", "vy", "density"))
    m = RHO0 * dx * dx
    cell = 2.0 * h
    grid = {}
    for i in idx:
        grid.setdefault((int(math.floor(x[i] / cell)), int(math.floor(y[i] / cell))), []).append(i)
    nbrs = {}
    for i in idx:
        cx, cy = int(math.floor(x[i] / cell)), int(math.floor(y[i] / cell))
        lst = []
        for a in (-1, 0, 1):
            for b in (-1, 0, 1):
                for j in grid.get((cx + a, cy + b), ()):
                    if j == i:
                        continue
                    rx, ry = x[j] - x[i], y[j] - y[i]
                    r = math.hypot(rx, ry)
                    if r < 2.0 * h:
                        w, wf = cubic(r, h)
                        lst.append((j, rx, ry, r, w, -wf))    # grad_i W_ij = wf (x_i - x_j) = -wf (x_j - x_i)
        nbrs[i] = lst
    def gradient(vx, vy):
        L = {}
        for i in idx:
            a = [0.0] * 4
            b = [0.0] * 4
            for j, rx, ry, r, w, g in nbrs[i]:
                vol = m / rho[j]
                gx, gy = g * rx, g * ry
                dvx, dvy = vx[j] - vx[i], vy[j] - vy[i]
                a[0] += vol * dvx * gx; a[1] += vol * dvx * gy; a[2] += vol * dvy * gx; a[3] += vol * dvy * gy
                b[0] += vol * rx * gx; b[1] += vol * rx * gy; b[2] += vol * ry * gx; b[3] += vol * ry * gy
            det = b[0] * b[3] - b[1] * b[2]
            if abs(det) < 1e-12 * max(1e-300, (abs(b[0]) + abs(b[3])) ** 2):
                bi = [1.0, 0.0, 0.0, 1.0]
            else:
                bi = [b[3] / det, -b[1] / det, -b[2] / det, b[0] / det]
            L[i] = [a[0] * bi[0] + a[1] * bi[2], a[0] * bi[1] + a[1] * bi[3],
                    a[2] * bi[0] + a[3] * bi[2], a[2] * bi[1] + a[3] * bi[3]]
        return L

    def eq_rate(l):
        """von Mises equivalent strain rate sqrt(2/3 D':D') of a 2d (plane strain) velocity gradient"""
        dxx, dyy, dxy = l[0], l[3], 0.5 * (l[1] + l[2])
        tr = (dxx + dyy) / 3.0
        return math.sqrt(2.0 / 3.0 * ((dxx - tr) ** 2 + (dyy - tr) ** 2 + tr * tr + 2.0 * dxy * dxy))

    L = gradient(vx, vy)
    res = {}
    for i in idx:
        se = sl = sw = 0.0
        px = py = pw = 0.0
        for j, rx, ry, r, w, g in nbrs[i]:
            lx = 0.5 * ((L[i][0] + L[j][0]) * rx + (L[i][1] + L[j][1]) * ry)
            ly = 0.5 * ((L[i][2] + L[j][2]) * rx + (L[i][3] + L[j][3]) * ry)
            ex, ey = vx[j] - vx[i] - lx, vy[j] - vy[i] - ly
            se += w * (ex * ex + ey * ey)
            sl += w * (lx * lx + ly * ly)
            sw += w
            vw = w * m / rho[j]
            # j's linear field at x_i: v_j + L_j (x_i - x_j), x_i - x_j = -(rx, ry)
            px += vw * (vx[j] - L[j][0] * rx - L[j][1] * ry)
            py += vw * (vy[j] - L[j][2] * rx - L[j][3] * ry)
            pw += vw
        if sw == 0.0:
            continue
        res[i] = [math.sqrt(se / sw), math.sqrt(sl / sw), (vx[i] - px / pw, vy[i] - py / pw)]
    # the strain rate with the residual removed: L of the velocities the neighbours predict
    # (v - d), against L of the velocities themselves
    vfx = {i: vx[i] - res[i][2][0] if i in res else vx[i] for i in range(len(vx))}
    vfy = {i: vy[i] - res[i][2][1] if i in res else vy[i] for i in range(len(vy))}
    Lf = gradient(vfx, vfy)
    for i in res:
        res[i] += [eq_rate(L[i]), eq_rate(Lf[i])]
    return res, nbrs


def regions(f, dx, vc):
    """particle index sets: contact layer (rake), 1, 2 and 4.5-6.5 spacings further, moving material"""
    cf, role, x, y = f["contact_feature"], f["role"], f["x"], f["y"]
    c1 = [i for i, fe in enumerate(cf) if fe == 1.0]
    out = {"moving": [i for i in range(len(x)) if role[i] == 0.0 and math.hypot(f["vx"][i], f["vy"][i]) > 0.01 * vc]}
    if not c1:
        return out
    out["contact"] = c1
    x1 = sum(x[i] for i in c1) / len(c1)
    ylo, yhi = min(y[i] for i in c1), max(y[i] for i in c1)
    for name, (lo, hi) in (("1 further", (0.5, 1.5)), ("2 further", (1.5, 2.5)), ("4.5-6.5 further", (4.5, 6.5))):
        out[name] = [i for i in range(len(x)) if role[i] == 0.0 and cf[i] == 0.0 and ylo <= y[i] <= yhi
                     and lo <= (x1 - x[i]) / dx < hi]
    return out


def region_stats(sel, res, nbrs, dx, vc):
    sel = [i for i in sel if i in res]
    if not sel:
        return None
    eta = sum(res[i][0] for i in sel) / len(sel) / vc
    ratio = math.sqrt(sum(res[i][0] ** 2 for i in sel) / max(1e-300, sum(res[i][1] ** 2 for i in sel)))
    num = den = 0.0
    for i in sel:
        di = res[i][2]
        for j, rx, ry, r, w, g in nbrs[i]:
            if j in res and r < 1.2 * dx:
                dj = res[j][2]
                num += di[0] * dj[0] + di[1] * dj[1]
                den += math.hypot(*di) * math.hypot(*dj)
    share = 1.0 - sum(res[i][4] for i in sel) / max(1e-300, sum(res[i][3] for i in sel))
    return eta, ratio, num / den if den > 0 else float("nan"), share


NAMES = ("contact", "1 further", "2 further", "4.5-6.5 further", "moving")


def run_stats(run, ny, vc_mpm=VC, hdx=1.3, quiet=False):
    dx = spacing(ny)
    vc = vc_mpm / 60.0
    cut = {}
    for line in open(os.path.join(run, "forces.dat")):    # step time cut_mm ...
        if line.strip() and not line.startswith("#"):
            v = line.split()
            cut[int(v[0])] = float(v[2])
    steps = sorted(cut)
    frames = read_frames(os.path.join(run, "dump.cutting"))
    lmax = max(cut.values())
    series, acc = [], {n: [] for n in NAMES}
    for step, f in frames:
        near = min(steps, key=lambda s: abs(s - step))
        lc = cut[near]
        if lc <= 0.0:
            continue
        res, nbrs = analyse(f, dx, hdx, vc)
        reg = regions(f, dx, vc)
        st = {n: region_stats(reg[n], res, nbrs, dx, vc) for n in NAMES if n in reg}
        series.append((lc, st))
        if lc >= STEADY_FROM * lmax:
            for n, v in st.items():
                if v is not None:
                    acc[n].append(v)
    mean = {n: [sum(v[k] for v in acc[n]) / len(acc[n]) for k in range(4)] for n in NAMES if acc[n]}
    if not quiet:
        print(f"{run}: {len(series)} frames in the cut, {len(acc['moving'])} after 10 % of it (dx {dx:.3g} m, "
              f"h {hdx} dx, vc {vc:.3g} m/s)")
        print(f"{'region':16s} {'eta/vc':>8s} {'eta/lin':>8s} {'C':>7s} {'share':>7s}")
        for n, (e, r, c, sh) in mean.items():
            print(f"{n:16s} {e:8.4f} {r:8.3f} {c:7.3f} {sh:7.3f}")
        print("against the cut length [mm]: eta/vc of the contact layer, of the moving material; C of the contact layer")
        for lc, st in series:
            c = st.get("contact")
            mv = st.get("moving")
            print(f"  {lc:6.3f}  {c[0] if c else float('nan'):8.4f}  {mv[0] if mv else float('nan'):8.4f}  "
                  f"{c[2] if c else float('nan'):7.3f}")
    return mean, series


def table(ny, runs):
    print("| run | eta/vc contact layer (eta/lin, C) | 1 further | 2 further | moving material | eta/vc contact layer, first / last third of the cut "
          "| strain-rate share of the residual: contact layer, 1 further |")
    print("|---|---|---|---|---|---|---|")
    for run in runs:
        mean, series = run_stats(run, ny, quiet=True)
        cells = []
        for n in ("contact", "1 further", "2 further", "moving"):
            e, r, c, sh = mean.get(n, [float("nan")] * 4)
            cells.append(f"{e:.4f} ({r:.2f}, {c:+.2f})")
        shares = f"{mean.get('contact', [0, 0, 0, float('nan')])[3]:.2f}, {mean.get('1 further', [0, 0, 0, float('nan')])[3]:.2f}"
        cs = [st["contact"][0] for lc, st in series if st.get("contact")]
        t = max(1, len(cs) // 3)
        grow = f"{sum(cs[:t]) / t:.4f} / {sum(cs[-t:]) / t:.4f}" if cs else "-"
        print(f"| {os.path.basename(run.rstrip('/'))} | " + " | ".join(cells) + f" | {grow} | {shares} |")


if __name__ == "__main__":
    if sys.argv[1] == "--table":
        table(int(sys.argv[2]), sys.argv[3:])
        sys.exit(0)
    a = sys.argv[1:]
    run_stats(a[0], int(a[1]), float(a[2]) if len(a) > 2 else VC, float(a[3]) if len(a) > 3 else 1.3)
