#!/usr/bin/env python3
"""The particles that ran away in a cutting run stopped by the watchdog of bench/gpu/cutting.sh
(mode watch): their state and their neighbours' at the stop, and their histories in the reruns.
Dumps are read by bench/cutting/hourglass.py's read_frames.
Usage: watch.py final.dump RERUN_DIR [RERUN_DIR ...] VBAD"""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "cutting"))
from hourglass import read_frames  # noqa: E402


def rows(frame):
    """the particles of a frame (dict column -> list) as dicts column -> value, by id"""
    cols = list(frame)
    return {int(v[0]): dict(zip(cols, v)) for v in zip(*(frame[c] for c in cols))}


def fmt(p):
    return " ".join(f"{k}={v:.4g}" for k, v in p.items())


def bad_ids(path, vbad):
    step, frame = read_frames(path)[-1]
    parts = rows(frame)
    return step, parts, [i for i, p in parts.items() if not math.hypot(p["vx"], p["vy"]) <= vbad]


def main():
    final, reruns, vbad = sys.argv[1], sys.argv[2:-1], float(sys.argv[-1])
    step, parts, ids = bad_ids(final, vbad)
    print(f"stop at step {step}: {len(ids)} particles faster than {vbad} m/s: {ids[:20]}")
    for i in ids[:5]:
        print("  bad", fmt(parts[i]))
    track = sorted(ids[:3])
    for d in reruns:
        fd = os.path.join(d, "final.dump")
        if os.path.exists(fd) and os.path.getsize(fd) > 0:
            s2, _, ids2 = bad_ids(fd, vbad)
            print(f"rerun {d}: stop at step {s2}: {len(ids2)} particles faster than {vbad} m/s: {ids2[:20]}")
        dump = os.path.join(d, "dump.cutting")
        if not os.path.exists(dump):
            continue
        print(f"history in {d} of {track} (every dump):")
        for k, (s, frame) in enumerate(read_frames(dump)):
            by_id = rows(frame)
            if k == 0 and track and track[0] in by_id:
                # the neighbours of the first tracked particle at the first snapshot
                p = by_id[track[0]]
                near = sorted(by_id.values(), key=lambda q: (q["x"] - p["x"]) ** 2 + (q["y"] - p["y"]) ** 2)[:12]
                print(f"  step {s}: the 12 nearest of {track[0]}:")
                for q in near:
                    print("   ", fmt(q))
            for i in track:
                if i in by_id:
                    print(f"  {s} {fmt(by_id[i])}")


if __name__ == "__main__":
    main()
