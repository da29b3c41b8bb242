#!/usr/bin/env python3
"""sphcut - a LAMMPS text dump (dump_sph or any dump custom) as a ParaView time series.

ParaView 5.11 (Debian bookworm) has no LAMMPS dump reader (unittest/test_paraview.py lists its
readers); this writes what it opens natively: one VTK unstructured grid (.vtu) per frame, the
particles as vertex cells at (x, y, z) (z = 0 for a 2D dump without z), every column of the
dump (id, type, x, ..., density, temperature, ...) as a point-data array under its column name,
and a .pvd index whose time values are the dump's time (ITEM: TIME, dump_modify time yes) or
else its time step.  Open the .pvd in ParaView (File > Open, or paraview PREFIX.pvd).

Usage: python tools/dump2vtu.py [-o PREFIX] DUMP [DUMP ...]
  DUMP     dump files in time order, several frames each; .gz files are read as gzip
  -o       output prefix (default: the first dump's name): writes PREFIX.pvd and PREFIX_<step>.vtu
Columns id, type, mol, proc, procp1, ix, iy, iz are written as 64-bit integers, every other
column as float64.  Positions are taken from x/y/z, else xu/yu/zu, else the scaled xs/ys/zs
(orthogonal boxes).  Needs numpy and meshio (the project's venv: tools/python-deps.sh).
"""
import argparse
import gzip
import os
import sys
import xml.sax.saxutils

import numpy as np

INT_COLUMNS = {"id", "type", "mol", "proc", "procp1", "ix", "iy", "iz"}


class DumpError(Exception):
    pass


def frames(path):
    """Yields (timestep, time or None, box bounds (3, 2+), column names, data (n, ncol) float64)."""
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "rt") as f:
        lineno = 0

        def line():
            nonlocal lineno
            s = f.readline()
            lineno += 1
            if not s:
                raise DumpError(f"{path}:{lineno}: unexpected end of file")
            return s.strip()

        while True:
            s = f.readline()
            lineno += 1
            if not s:
                return
            if not s.strip():
                continue
            step = time = natoms = None
            box = None
            while True:
                if not s:
                    raise DumpError(f"{path}:{lineno}: unexpected end of file in the header of a frame")
                if not s.startswith("ITEM:"):
                    raise DumpError(f"{path}:{lineno}: expected an 'ITEM:' line, got '{s.strip()[:60]}'")
                item = s[5:].strip()
                if item == "TIMESTEP":
                    step = int(line())
                elif item == "TIME":
                    time = float(line())
                elif item == "UNITS":
                    line()
                elif item == "NUMBER OF ATOMS":
                    natoms = int(line())
                elif item.startswith("BOX BOUNDS"):
                    box = np.array([[float(v) for v in line().split()] for _ in range(3)])
                elif item.startswith("ATOMS"):
                    names = item.split()[1:]
                    break
                else:
                    raise DumpError(f"{path}:{lineno}: unknown header 'ITEM: {item}'")
                s = f.readline()
                lineno += 1
            if step is None or natoms is None or box is None:
                raise DumpError(f"{path}:{lineno}: frame without TIMESTEP, NUMBER OF ATOMS or BOX BOUNDS")
            if len(set(names)) != len(names):
                raise DumpError(f"{path}:{lineno}: a column name appears twice: {' '.join(names)}")
            text = "".join(f.readline() for _ in range(natoms))
            data = np.fromstring(text, sep=" ") if natoms else np.zeros(0)
            if data.size != natoms * len(names):
                raise DumpError(f"{path}: time step {step}: {data.size} values for {natoms} atoms x "
                                f"{len(names)} columns (a truncated frame or a non-numeric column)")
            lineno += natoms
            yield step, time, box, names, data.reshape(natoms, len(names))


def positions(names, data, box):
    col = {n: i for i, n in enumerate(names)}
    for triple, scaled in ((("x", "y", "z"), False), (("xu", "yu", "zu"), False), (("xs", "ys", "zs"), True)):
        if triple[0] in col and triple[1] in col:
            if scaled and box.shape[1] > 2:
                raise DumpError("scaled coordinates (xs ys zs) of a triclinic box: dump x y z instead")
            pts = np.zeros((len(data), 3))
            for d, n in enumerate(triple):
                if n in col:
                    pts[:, d] = data[:, col[n]]
                    if scaled:
                        pts[:, d] = box[d, 0] + pts[:, d] * (box[d, 1] - box[d, 0])
            return pts
    raise DumpError("the dump has no positions (columns x y [z], xu yu [zu] or xs ys [zs])")


def convert(dumps, prefix):
    import meshio

    if os.path.dirname(prefix):
        os.makedirs(os.path.dirname(prefix), exist_ok=True)
    written = []   # (time value, file name)
    steps = set()
    for path in dumps:
        for step, time, box, names, data in frames(path):
            if step in steps:
                print(f"dump2vtu: {path}: time step {step} again, skipped", file=sys.stderr)
                continue
            steps.add(step)
            pts = positions(names, data, box)
            point_data = {}
            for i, n in enumerate(names):
                point_data[n] = data[:, i].astype(np.int64) if n in INT_COLUMNS else data[:, i].copy()
            cells = [("vertex", np.arange(len(pts), dtype=np.int64).reshape(-1, 1))]
            vtu = f"{prefix}_{step}.vtu"
            meshio.write(vtu, meshio.Mesh(pts, cells, point_data=point_data), file_format="vtu")
            written.append((time if time is not None else step, vtu))
    if not written:
        raise DumpError("no frames in " + " ".join(dumps))
    pvd = prefix + ".pvd"
    base = os.path.dirname(os.path.abspath(pvd))
    with open(pvd, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n')
        for t, vtu in written:
            rel = os.path.relpath(os.path.abspath(vtu), base)
            f.write(f'    <DataSet timestep="{t!r}" part="0" file={xml.sax.saxutils.quoteattr(rel)}/>\n')
        f.write("  </Collection>\n</VTKFile>\n")
    return pvd, len(written)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dumps", nargs="+", metavar="DUMP")
    ap.add_argument("-o", "--prefix", help="output prefix (default: the first dump's name)")
    a = ap.parse_args(argv)
    prefix = a.prefix or (a.dumps[0][:-3] if a.dumps[0].endswith(".gz") else a.dumps[0])
    try:
        pvd, n = convert(a.dumps, prefix)
    except (DumpError, OSError, ValueError) as e:
        sys.exit(f"dump2vtu: ERROR: {e}")
    print(f"dump2vtu: {n} frames -> {pvd}")


if __name__ == "__main__":
    main()
