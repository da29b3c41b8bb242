#!/usr/bin/env python3
"""Plastic power of the contact layer against the friction power (issue 13, item 4), from a
dump of examples/cutting-2d-ti6al4v (dump.cutting: its default columns).  Per unit thickness,
mean over the frames after FIRST_STEP:
  friction power  sum over particles in contact of |F_T| times the sliding speed (on the rake
                  face |vy|, elsewhere the speed relative to the tool);
  plastic power   sum of von Mises stress x equivalent plastic strain rate x volume m/rho, for
                  the particles in contact, for those within 2 spacings in front of the rake face
                  (not in contact, above the tool tip), and for the whole workpiece.
Usage: interface_power.py DUMP [NY (11)] [FIRST_STEP (20000)] [VC m/min (318.5)]"""
import math
import statistics
import sys

from hourglass import read_frames    # the dump reader of this folder
from seed003 import RHO0, VC, spacing    # noqa: E402 (hourglass.py puts the example on the path)


def main():
    path = sys.argv[1]
    ny = int(sys.argv[2]) if len(sys.argv) > 2 else 11
    first = int(sys.argv[3]) if len(sys.argv) > 3 else 20000
    vc = (float(sys.argv[4]) if len(sys.argv) > 4 else VC) / 60.0
    dx, rho0, ytip = spacing(ny), RHO0, 0.2e-3
    rows = []
    for step, f in read_frames(path):
        tool = [k for k, t in enumerate(f["type"]) if t == 2]
        if step < first or not tool:
            continue
        xrake = min(f["x"][k] for k in tool)
        fric = layer = nextl = total = 0.0
        ncont = 0
        for k, t in enumerate(f["type"]):
            if t != 1:
                continue
            power = f["vonmises"][k] * f["plastic_strain_rate"][k] * rho0 * dx * dx / f["density"][k]
            total += power
            feat = int(f["contact_feature"][k])
            if feat > 0:
                vx, vy = f["vx"][k], f["vy"][k]
                slide = abs(vy) if feat == 1 else math.hypot(vx + vc, vy)
                fric += f["fcontact_t"][k] * slide
                layer += power
                ncont += 1
            elif xrake - 2.0 * dx < f["x"][k] < xrake and f["y"][k] > ytip - 0.5 * dx:
                nextl += power
        rows.append((fric, layer, nextl, total, ncont))
    if not rows:
        sys.exit(f"no frame after step {first} with tool particles in {path}")
    m = [statistics.mean(r[k] for r in rows) for k in range(5)]
    print(f"{len(rows)} frames from step {first}, per unit thickness [kW/m]:")
    print(f"  friction power of the contact                          {m[0] / 1e3:8.1f}")
    print(f"  plastic power of the particles in contact ({m[4]:.1f} on average) {m[1] / 1e3:8.1f}")
    print(f"  plastic power within 2 spacings in front of the rake face {m[2] / 1e3:8.1f}")
    print(f"  plastic power of the whole workpiece                   {m[3] / 1e3:8.1f}")


if __name__ == "__main__":
    main()
