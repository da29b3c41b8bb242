#!/usr/bin/env python3
"""The particles that ran away in a cutting run stopped by the watchdog of bench/gpu/cutting.sh
(mode watch): their state and their neighbours' at the stop, and their histories in the reruns.
Usage: watch.py final.dump RERUN_DIR [RERUN_DIR ...] VBAD"""
import math
import os
import sys


def snapshots(path):
    """yield (step, columns, rows) of a LAMMPS text dump; rows: list of float lists"""
    with open(path) as f:
        while True:
            line = f.readline()
            if not line:
                return
            if not line.startswith("ITEM: TIMESTEP"):
                continue
            step = int(f.readline())
            f.readline()
            n = int(f.readline())
            for _ in range(4):
                f.readline()
            cols = f.readline().split()[2:]
            rows = [[float(v) for v in f.readline().split()] for _ in range(n)]
            yield step, cols, rows


def last(path):
    out = None
    for snap in snapshots(path):
        out = snap
    return out


def speed(c, r):
    return math.hypot(r[c.index("vx")], r[c.index("vy")])


def fmt(c, r):
    return " ".join(f"{k}={r[c.index(k)]:.4g}" for k in c)


def bad_ids(path, vbad):
    step, c, rows = last(path)
    return step, c, rows, [int(r[0]) for r in rows if not speed(c, r) <= vbad]


def main():
    final, reruns, vbad = sys.argv[1], sys.argv[2:-1], float(sys.argv[-1])
    step, c, rows, ids = bad_ids(final, vbad)
    print(f"stop at step {step}: {len(ids)} particles faster than {vbad} m/s: {ids[:20]}")
    ix, iy = c.index("x"), c.index("y")
    by_id = {int(r[0]): r for r in rows}
    for i in ids[:5]:
        r = by_id[i]
        print("  bad", fmt(c, r))
    for d in reruns:
        fd = os.path.join(d, "final.dump")
        if os.path.exists(fd) and os.path.getsize(fd) > 0:
            s2, c2, rows2, ids2 = bad_ids(fd, vbad)
            print(f"rerun {d}: stop at step {s2}: {len(ids2)} particles faster than {vbad} m/s: {ids2[:20]}")
        track = set(ids[:3])
        dump = os.path.join(d, "dump.cutting")
        if not os.path.exists(dump):
            continue
        print(f"history in {d} of {sorted(track)} (every dump):")
        first = True
        for s, cc, rr in snapshots(dump):
            rid = {int(r[0]): r for r in rr}
            if first:
                # the neighbours of the first tracked particle at the first snapshot
                first = False
                if track and min(track) in rid:
                    p = rid[min(track)]
                    near = sorted(rr, key=lambda r: (r[cc.index("x")] - p[cc.index("x")]) ** 2 +
                                  (r[cc.index("y")] - p[cc.index("y")]) ** 2)[:12]
                    print(f"  step {s}: the 12 nearest of {min(track)}:")
                    for r in near:
                        print("   ", fmt(cc, r))
            for i in sorted(track):
                if i in rid:
                    print(f"  {s} {fmt(cc, rid[i])}")


if __name__ == "__main__":
    main()
