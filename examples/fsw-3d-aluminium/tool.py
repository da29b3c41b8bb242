#!/usr/bin/env python3
"""Friction stir welding tool for fix contact/tri-penalty: a cylindrical shoulder with a threadless
pin (cylindrical, or conical with --Rtip < --Rpin), a closed solid of revolution about z written as an
ASCII STL with outward normals.  The pin's tip centre is at (cx, cy, cz); the pin runs up to the
shoulder face at cz + Lpin; the shoulder (radius Rs) is Hs high above it.  Usage:
  python3 tool.py -o tool.stl --Rs 10e-3 --Rpin 3e-3 --Rtip 3e-3 --Lpin 5.7e-3 [--Hs 3e-3 --nseg 48
                  --cx 0 --cy 0 --cz 0 --info tool.in]
(lengths in m).  --info writes, as LAMMPS variables, the angle (deg, counter-clockwise from +x about
+z) of the centroid of facet 1 (a side facet of the pin) about the axis: the input follows the turned
tool with it."""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
from stl_ascii import facet  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-o", "--out", default="tool.stl")
    ap.add_argument("--Rs", type=float, default=10e-3, help="shoulder radius (m)")
    ap.add_argument("--Rpin", type=float, default=3e-3, help="pin radius at the shoulder (m)")
    ap.add_argument("--Rtip", type=float, default=-1.0, help="pin radius at the tip (m; default Rpin)")
    ap.add_argument("--Lpin", type=float, default=5.7e-3, help="pin length (m)")
    ap.add_argument("--Hs", type=float, default=3e-3, help="shoulder height above its face (m)")
    ap.add_argument("--nseg", type=int, default=48, help="facets around the circumference")
    ap.add_argument("--cx", type=float, default=0.0)
    ap.add_argument("--cy", type=float, default=0.0)
    ap.add_argument("--cz", type=float, default=0.0)
    ap.add_argument("--info", default="")
    o = ap.parse_args()
    rtip = o.Rpin if o.Rtip < 0 else o.Rtip
    if not (0 < rtip <= o.Rpin < o.Rs and o.Lpin > 0 and o.Hs > 0 and o.nseg >= 8):
        sys.exit("tool.py: need 0 < Rtip <= Rpin < Rs, Lpin > 0, Hs > 0, nseg >= 8")
    # the profile (r, z) from the tip's centre round to the top's centre; revolving it about z
    prof = [(rtip, 0.0), (o.Rpin, o.Lpin), (o.Rs, o.Lpin), (o.Rs, o.Lpin + o.Hs)]
    n = o.nseg
    ang = [2.0 * math.pi * k / n for k in range(n + 1)]

    def P(r, z, k):
        return (o.cx + r * math.cos(ang[k % n]), o.cy + r * math.sin(ang[k % n]), o.cz + z)

    nf = 0
    first = None
    with open(o.out, "w") as out:
        out.write("solid fswtool\n")
        # side bands first (facet 1: the pin's side between angles 0 and 360/n)
        for (r0, z0), (r1, z1) in zip(prof[:-1], prof[1:]):
            for k in range(n):
                a, b = P(r0, z0, k), P(r0, z0, k + 1)
                c, d = P(r1, z1, k + 1), P(r1, z1, k)
                # outward: counter-clockwise seen from outside; the profile runs up/out
                for tri in ((a, b, c), (a, c, d)):
                    if math.dist(tri[0], tri[1]) > 0 and math.dist(tri[1], tri[2]) > 0 and math.dist(tri[0], tri[2]) > 0:
                        facet(out, *tri)
                        nf += 1
                        if first is None:
                            first = [sum(q[i] for q in tri) / 3.0 for i in range(3)]
        # the pin's tip (bottom, normal -z) and the shoulder's top (normal +z) as fans
        zt = o.Lpin + o.Hs
        for k in range(n):
            facet(out, (o.cx, o.cy, o.cz), P(rtip, 0.0, k + 1), P(rtip, 0.0, k))
            facet(out, (o.cx, o.cy, o.cz + zt), P(o.Rs, zt, k), P(o.Rs, zt, k + 1))
            nf += 2
        out.write("endsolid fswtool\n")
    if o.info:
        with open(o.info, "w") as f:
            f.write("variable cang0 equal %.17g\n" % math.degrees(math.atan2(first[1] - o.cy, first[0] - o.cx)))
    print("tool.py: shoulder radius %g m, pin radius %g m (tip %g m), pin length %g m, %d facets -> %s"
          % (o.Rs, o.Rpin, rtip, o.Lpin, nf, o.out))


if __name__ == "__main__":
    main()
