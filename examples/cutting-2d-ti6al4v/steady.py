#!/usr/bin/env python3
"""Steady-state cutting forces: mean Fc and Ft after 10 % of the cut (as seed 003 does), with the
standard error of the mean from 5 block means, printed beside the experiment and the paper's SPH
results.  Reads forces.dat."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from seed003 import EXP, LOWSPEED_T_EXP, LOWSPEED_T_PAPER, PAPER, block_error, steady_rows  # noqa: E402


def read_rows(path="forces.dat"):
    """rows [time, cut_mm, Fc, Ft, Tmax, Trake] in step order; a run continued from a restart
    repeats the step it started from: the last line of each step is kept"""
    by_step = {}
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            v = line.split()
            by_step[int(v[0])] = [float(x) for x in v[1:]]
    return [by_step[k] for k in sorted(by_step)]


def main(path="forces.dat", temperature_only=False):
    rows = read_rows(path)
    lmax, sel = steady_rows(rows)
    fc = sum(r[2] for r in sel) / len(sel)
    ft = sum(r[3] for r in sel) / len(sel)
    trake = sum(r[5] for r in sel) / len(sel) if len(sel[0]) > 5 else float("nan")
    print(f"steady state over {0.1 * lmax:.3f}-{lmax:.3f} mm of cut ({len(sel)} samples)")
    if temperature_only:
        # the paper's figure is the frame's mean at the end of the cut (seed 003 Fig. 8); the
        # frame still warms at 0.3 mm, so the mean over the cut and that at its end differ
        end = [r[5] for r in rows if r[1] >= 0.9 * lmax] if len(sel[0]) > 5 else []
        tend = sum(end) / len(end) if end else float("nan")
        print(f"rake-face temperature {tend:.0f} K over the last 10 % of the cut ({0.9 * lmax:.3f}-{lmax:.3f} mm)")
        print(f"mean rake-face temperature {trake:.0f} K (low-speed case vc 20 m/min: measured about "
              f"{LOWSPEED_T_EXP:.0f} K, paper's SPH {LOWSPEED_T_PAPER:.0f} K); Fc {fc:.1f} N/mm, Ft {ft:.1f} N/mm")
        return
    print(f"{'':44s} {'Fc [N/mm]':>10s} {'Ft [N/mm]':>10s}")
    efc, eft = block_error([r[2] for r in sel]), block_error([r[3] for r in sel])
    print(f"{'sphcut':44s} {fc:10.1f} {ft:10.1f}   ({100*(fc/EXP[0]-1):+.0f} %, {100*(ft/EXP[1]-1):+.0f} %; "
          f"standard error of 5 block means {efc:.1f}, {eft:.1f})")
    print(f"{'experiment':44s} {EXP[0]:10.1f} {EXP[1]:10.1f}")
    for k, (a, b) in PAPER.items():
        print(f"{k:44s} {a:10.1f} {b:10.1f}   ({100*(a/EXP[0]-1):+.0f} %, {100*(b/EXP[1]-1):+.0f} %)")
    print(f"mean rake-face temperature {trake:.0f} K")


if __name__ == "__main__":
    main(temperature_only="--temperature" in sys.argv)
