#!/usr/bin/env python3
"""Steady-state forces of finished cutting runs side by side.
Usage: summarise.py RUN ...   (RUN = a folder or a .tar.gz from device-cut.sh, or a variant folder of
sensitivity.sh, holding forces.dat and log.*).  Mean Fc, Ft and rake-face temperature after 10 % of the cut
(examples/cutting-2d-ti6al4v/steady.py), the cut length reached, steps and loop time."""
import io
import os
import re
import sys
import tarfile

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "examples", "cutting-2d-ti6al4v"))
from seed003 import EXP, steady_rows  # noqa: E402
from steady import read_rows  # noqa: E402


def files_of(run):
    if run.endswith(".tar.gz"):
        with tarfile.open(run) as t:
            return {os.path.basename(m.name): t.extractfile(m).read().decode() for m in t.getmembers()
                    if m.isfile() and (m.name.endswith("forces.dat") or "log." in m.name)}
    return {f: open(os.path.join(run, f)).read() for f in os.listdir(run) if f == "forces.dat" or f.startswith("log.")}


print(f"{'run':36s} {'cut mm':>7s} {'Fc N/mm':>9s} {'Ft N/mm':>9s} {'Trake K':>8s} {'steps':>8s} {'loop s':>8s}")
for run in sys.argv[1:]:
    f = files_of(run)
    path = "/tmp/_forces.dat"
    with open(path, "w") as out:
        out.write(f["forces.dat"])
    rows = read_rows(path)
    lmax, sel = steady_rows(rows)
    fc, ft = (sum(r[k] for r in sel) / len(sel) for k in (2, 3))
    tr = sum(r[5] for r in sel) / len(sel)
    steps, loop = 0, 0.0
    for name, text in f.items():
        for m in re.finditer(r"Loop time of ([0-9.e+-]+) on \d+ procs for (\d+) steps", text):
            loop += float(m.group(1))
            steps += int(m.group(2))
    name = os.path.basename(run).replace(".tar.gz", "")
    print(f"{name:36s} {lmax:7.3f} {fc:9.1f} {ft:9.1f} {tr:8.0f} {steps:8d} {loop:8.0f}"
          f"   ({100 * (fc / EXP[0] - 1):+.0f} %, {100 * (ft / EXP[1] - 1):+.0f} %)")
