#!/usr/bin/env python3
"""Two-flute (or Z-flute) milling cutter for fix contact/tri-penalty: the 2D cross-section (a disc
with Z teeth, each with a rake face, a sharp cutting edge and a clearance face) extruded over
z in [-W/2, W/2] into a closed ASCII STL with outward normals (the fix takes its section with z = 0).

Angle convention (Altintas): the cutter turns clockwise seen from +z (fix contact/tri-penalty
spin 0 0 -1 ...), the tooth angle phi is measured clockwise from +y; tooth k's tip is at
R (sin phi_k, cos phi_k), phi_k = phi0 + 360 k / Z, its rake face faces the direction of motion
m = (cos phi, -sin phi).  The rake face runs from the tip inward over the gullet depth d, leaning
back by the rake angle; the clearance face runs back from the tip over flank_length at the
clearance angle below the tangent; then the heel drops to the core radius R - d, whose arc
runs to the next rake face.  Usage:
  python3 cutter.py -o cutter.stl --R 1e-3 --teeth 2 --phi0 -5 [--rake 0 --clearance 7 --gullet 0.3 --flank 0.1
                    --rn 38e-6 --info cutter.in]
(--gullet and --flank as fractions of R; lengths in m).  With an edge radius rn the corner of rake
face and flank is an arc tangent to both (8 chords): the teeth then reach out to the envelope
radius Renv < R (--info writes it, and the angle of the centroid of the first side facet, as
LAMMPS variables)."""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
from stl_ascii import facet  # noqa: E402


def fillet(T, ur, uf, rn, nseg):
    """The corner T between the rake face (direction ur from T) and the flank (uf from T) rounded
    with radius rn in nseg chords: the points from the rake face's tangent point to the flank's."""
    if rn <= 0.0:
        return [T]
    beta = math.acos(max(-1.0, min(1.0, ur[0] * uf[0] + ur[1] * uf[1])))     # wedge angle
    t = rn / math.tan(0.5 * beta)
    bis = (ur[0] + uf[0], ur[1] + uf[1])
    lb = math.hypot(*bis)
    C = (T[0] + bis[0] / lb * rn / math.sin(0.5 * beta), T[1] + bis[1] / lb * rn / math.sin(0.5 * beta))
    Pr = (T[0] + t * ur[0], T[1] + t * ur[1])
    Pf = (T[0] + t * uf[0], T[1] + t * uf[1])
    a0 = math.atan2(Pr[1] - C[1], Pr[0] - C[0])
    a1 = math.atan2(Pf[1] - C[1], Pf[0] - C[0])
    sweep = math.pi - beta                                                  # the arc turns by 180 - wedge
    if (a1 - a0) % (2 * math.pi) > math.pi:                                 # the short way round
        sweep = -sweep
    return [(C[0] + rn * math.cos(a0 + sweep * i / nseg), C[1] + rn * math.sin(a0 + sweep * i / nseg))
            for i in range(nseg + 1)]


def outline(R, Z, phi0, rake, clearance, gullet, flank, rn=0.0, nedge=8, narc=12):
    """Polygon vertices, counter-clockwise (math sense: against the cutter's rotation)."""
    d, lf = gullet * R, flank * R
    g, a = math.radians(rake), math.radians(clearance)
    Rb = R - d
    pitch = 2.0 * math.pi / Z
    pts = []
    for j in range(Z):
        k = (-j) % Z                     # decreasing phi: tooth 0, Z-1, ..., 1
        ph = math.radians(phi0) + k * pitch
        r = (math.sin(ph), math.cos(ph))
        m = (math.cos(ph), -math.sin(ph))
        T = (R * r[0], R * r[1])
        F = (T[0] - lf * (math.cos(a) * m[0] + math.sin(a) * r[0]),
             T[1] - lf * (math.cos(a) * m[1] + math.sin(a) * r[1]))
        ur = (-r[0] - math.tan(g) * m[0], -r[1] - math.tan(g) * m[1])       # rake face, from the tip inward
        lu = math.hypot(*ur)
        ur = (ur[0] / lu, ur[1] / lu)
        uf = (-(math.cos(a) * m[0] + math.sin(a) * r[0]), -(math.cos(a) * m[1] + math.sin(a) * r[1]))
        pts += fillet(T, ur, uf, rn, nedge) + [F]
        # heel: from F down to the core circle 0.15 pitch behind the flank's end
        phF = math.atan2(F[0], F[1])
        ph_heel = phF - 0.15 * pitch
        # the rake face of the tooth behind (phi - pitch): from its tip inward by d, leaning back by g
        pb = ph - pitch
        rb = (math.sin(pb), math.cos(pb))
        mb = (math.cos(pb), -math.sin(pb))
        Tb = (R * rb[0], R * rb[1])
        G = (Tb[0] - d * rb[0] - d * math.tan(g) * mb[0], Tb[1] - d * rb[1] - d * math.tan(g) * mb[1])
        phG = math.atan2(G[0], G[1])
        while phG > ph_heel:
            phG -= 2.0 * math.pi
        for i in range(narc):            # core arc from the heel back towards the gullet's floor at G
            t = ph_heel + (phG - ph_heel) * i / narc
            pts.append((Rb * math.sin(t), Rb * math.cos(t)))
        pts.append(G)
        # (Tb is the first vertex of the next tooth)
    return pts


def area(p):
    return 0.5 * sum(p[i][0] * p[(i + 1) % len(p)][1] - p[(i + 1) % len(p)][0] * p[i][1] for i in range(len(p)))


def ear_clip(p):
    """Triangles (index triples, counter-clockwise) of a simple counter-clockwise polygon."""
    idx = list(range(len(p)))
    tris = []

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    def inside(q, a, b, c):
        return cross(a, b, q) > 0 and cross(b, c, q) > 0 and cross(c, a, q) > 0

    guard = 0
    while len(idx) > 3:
        guard += 1
        if guard > 100000:
            sys.exit("cutter.py: ear clipping failed (self-intersecting outline?)")
        n = len(idx)
        for i in range(n):
            ia, ib, ic = idx[(i - 1) % n], idx[i], idx[(i + 1) % n]
            a, b, c = p[ia], p[ib], p[ic]
            if cross(a, b, c) <= 1e-9 * math.dist(a, b) * math.dist(b, c):    # reflex or (nearly) collinear
                continue
            if any(inside(p[j], a, b, c) for j in idx if j not in (ia, ib, ic)):
                continue
            tris.append((ia, ib, ic))
            del idx[i]
            break
        else:
            sys.exit("cutter.py: no ear found (self-intersecting outline?)")
    tris.append(tuple(idx))
    return tris


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-o", "--out", default="cutter.stl")
    ap.add_argument("--R", type=float, default=1e-3, help="cutter radius (m)")
    ap.add_argument("--teeth", type=int, default=2)
    ap.add_argument("--phi0", type=float, default=0.0, help="angle of tooth 0 (deg, clockwise from +y)")
    ap.add_argument("--rake", type=float, default=0.0, help="rake angle (deg)")
    ap.add_argument("--clearance", type=float, default=7.0, help="clearance angle (deg)")
    ap.add_argument("--gullet", type=float, default=0.3, help="gullet depth / R")
    ap.add_argument("--flank", type=float, default=0.1, help="clearance face length / R")
    ap.add_argument("--rn", type=float, default=0.0, help="cutting-edge radius (m; 0: sharp)")
    ap.add_argument("--info", default="", help="also write LAMMPS variables of the geometry to this file")
    ap.add_argument("--cx", type=float, default=0.0)
    ap.add_argument("--cy", type=float, default=0.0)
    o = ap.parse_args()
    if o.teeth < 1 or o.R <= 0 or not 0 < o.gullet < 0.9 or not 0 < o.flank or not 0 <= o.clearance < 45:
        sys.exit("cutter.py: need teeth >= 1, R > 0, 0 < gullet < 0.9, flank > 0, 0 <= clearance < 45")
    if o.rn < 0 or o.rn > 0.5 * o.flank * o.R:
        sys.exit("cutter.py: need 0 <= rn <= flank R / 2")
    p = outline(o.R, o.teeth, o.phi0, o.rake, o.clearance, o.gullet, o.flank, o.rn)
    renv = max(math.hypot(x, y) for x, y in p)         # the teeth's envelope (the rounded edge lies inside R)
    p = [(x + o.cx, y + o.cy) for x, y in p]
    if area(p) <= 0:
        sys.exit("cutter.py: the outline is not counter-clockwise (check the parameters)")
    tris = ear_clip(p)
    w = 0.5 * o.R
    with open(o.out, "w") as out:
        out.write("solid cutter\n")
        n = len(p)
        for i in range(n):                    # side faces, outward
            a, b = p[i], p[(i + 1) % n]
            facet(out, (a[0], a[1], -w), (b[0], b[1], -w), (b[0], b[1], w))
            facet(out, (a[0], a[1], -w), (b[0], b[1], w), (a[0], a[1], w))
        for i, j, k in tris:                  # caps: top counter-clockwise seen from +z, bottom reversed
            facet(out, (*p[i], w), (*p[j], w), (*p[k], w))
            facet(out, (*p[i], -w), (*p[k], -w), (*p[j], -w))
        out.write("endsolid cutter\n")
    if o.info:
        # the first side facet (edge p0 -> p1: tooth 0's tip -> the end of its clearance face) cuts
        # the plane z = 0 in the segment from p1 to the middle of p0-p1 (see the facet's vertices):
        # its centroid (p0 + 3 p1) / 4 and that point's angle about the axis, clockwise from +y
        c = [(p[0][k] + 3.0 * p[1][k]) / 4.0 for k in range(2)]
        with open(o.info, "w") as f:
            f.write("variable cang0 equal %.17g\n" % math.degrees(math.atan2(c[0] - o.cx, c[1] - o.cy)))
            f.write("variable Renv equal %.17g\n" % renv)
    print("cutter.py: %d teeth, R %g m, edge radius %g m, envelope radius %.9g m, %d outline vertices, "
          "section area %.6g m^2 -> %s" % (o.teeth, o.R, o.rn, renv, len(p), area(p), o.out))


if __name__ == "__main__":
    main()
