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
(orthogonal boxes).  A file that ends inside a frame (a dump still being written, or cut off) gives
the frames before that one, with a warning naming it; a file that is not a text dump (binary, a
value that is not a number, ...) stops with one line naming the file, the frame and the line, and
leaves nothing written (exit status 1).  Needs numpy and meshio (the project's venv: tools/python-deps.sh).
"""
import argparse
import gzip
import os
import re
import sys
import warnings
import xml.sax.saxutils
import zlib

import numpy as np

INT_COLUMNS = {"id", "type", "mol", "proc", "procp1", "ix", "iy", "iz"}


class DumpError(Exception):
    pass


class Truncated(Exception):
    """The file ends inside a frame (a dump still being written, or cut): the frames before it stand."""


def frames(path):
    """Yields (timestep, time or None, box bounds (3, 2+), column names, data (n, ncol) float64).
    Raises Truncated where the file ends inside a frame, DumpError where it is not a LAMMPS text
    dump; each names the file, the frame (its time step, where read) and the line."""
    opener = gzip.open if path.endswith(".gz") else open
    lineno = 0
    step = None

    def where():
        return f"{path}: line {lineno}" + (f" (the frame of time step {step})" if step is not None else "")

    def text(s, first):
        """s (lines from line first on) as read: a byte that is not UTF-8 text is an error at its line"""
        nonlocal lineno
        m = _NOT_UTF8.search(s)
        if m:
            lineno = first + s.count("\n", 0, m.start())
            raise DumpError(f"{where()}: not a text dump (byte 0x{ord(m.group()) - 0xdc00:02x} is not UTF-8 text)")
        return s

    try:
        # undecodable bytes pass as surrogates, so that text() finds the line they are in
        with opener(path, "rt", errors="surrogateescape") as f:

            def line():
                nonlocal lineno
                s = f.readline()
                lineno += 1
                if not s:
                    raise Truncated(f"{where()}: the file ends inside the frame's header")
                return text(s, lineno).strip()

            def number(kind, s):
                try:
                    return kind(s)
                except ValueError:
                    raise DumpError(f"{where()}: '{s[:60]}' is not a{'n integer' if kind is int else ' number'}") \
                        from None

            while True:
                s = text(f.readline(), lineno + 1)
                lineno += 1
                if not s:
                    return
                if not s.strip():
                    continue
                step = time = natoms = None
                box = None
                while True:
                    if not s:
                        raise Truncated(f"{where()}: the file ends inside the frame's header")
                    if not s.startswith("ITEM:"):
                        raise DumpError(f"{where()}: expected an 'ITEM:' line, got '{s.strip()[:60]}'")
                    item = s[5:].strip()
                    if item == "TIMESTEP":
                        step = number(int, line())
                    elif item == "TIME":
                        time = number(float, line())
                    elif item == "UNITS":
                        line()
                    elif item == "NUMBER OF ATOMS":
                        natoms = number(int, line())
                    elif item.startswith("BOX BOUNDS"):
                        box = []
                        for _ in range(3):
                            box.append([number(float, v) for v in line().split()])
                        if len({len(b) for b in box}) != 1 or len(box[0]) < 2:
                            raise DumpError(f"{where()}: BOX BOUNDS rows of unequal length or fewer than 2 values")
                        box = np.array(box)
                    elif item.startswith("ATOMS"):
                        names = item.split()[1:]
                        break
                    else:
                        raise DumpError(f"{where()}: unknown header 'ITEM: {item}'")
                    s = text(f.readline(), lineno + 1)
                    lineno += 1
                if step is None or natoms is None or box is None:
                    raise DumpError(f"{where()}: frame without TIMESTEP, NUMBER OF ATOMS or BOX BOUNDS")
                if len(set(names)) != len(names):
                    raise DumpError(f"{where()}: a column name appears twice: {' '.join(names)}")
                first = lineno + 1    # the line of the frame's first atom
                rows = []
                for _ in range(natoms):
                    r = text(f.readline(), lineno + 1)
                    if not r.endswith("\n"):    # the file ends in this row (or before it)
                        lineno += 1 if r else 0
                        raise Truncated(f"{where()}: the file ends inside the frame's atom rows")
                    rows.append(r)
                    lineno += 1
                body = "".join(rows)
                with warnings.catch_warnings():
                    warnings.simplefilter("error")    # numpy's note on unmatched data: an error here
                    try:
                        data = np.fromstring(body, sep=" ") if natoms else np.zeros(0)
                    except (ValueError, DeprecationWarning):
                        data = None
                if data is None or data.size != natoms * len(names):
                    for k, r in enumerate(rows):    # the first row that is not ncol numbers
                        v = r.split()
                        bad = [x for x in v if not _is_number(x)]
                        if bad or len(v) != len(names):
                            lineno = first + k
                            what = f"'{bad[0][:40]}' is not a number" if bad else \
                                f"{len(v)} values for the {len(names)} columns"
                            raise DumpError(f"{where()}: {what}")
                    raise DumpError(f"{where()}: the atom rows do not hold {natoms} x {len(names)} numbers")
                yield step, time, box, names, data.reshape(natoms, len(names))
                step = None    # between frames
    except EOFError:    # gzip: the compressed stream ends early
        raise Truncated(f"{where()}: the compressed file ends early") from None
    except (gzip.BadGzipFile, zlib.error) as e:
        raise DumpError(f"{where() if lineno else path}: not a valid gzip file ({e})") from None


_NOT_UTF8 = re.compile("[\udc80-\udcff]")


def last_frame(path):
    """(time step, column names, data (n, ncol) float64) of the last frame of a dump, as frames()
    reads it (its errors likewise); (None, None, None) for a dump without a frame"""
    last = (None, None, None)
    for step, _time, _box, names, data in frames(path):
        last = (step, names, data)
    return last

def _is_number(s):
    try:
        float(s)
        return True
    except ValueError:
        return False


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
    """Writes the .vtu of each complete frame and the .pvd of them all; returns (pvd, frames, notes).
    A file that ends inside a frame (Truncated) gives the frames before it and a note naming the cut
    frame; any other error (DumpError, OSError) removes the .vtu files written and leaves nothing."""
    import meshio

    if os.path.dirname(prefix):
        os.makedirs(os.path.dirname(prefix), exist_ok=True)
    written = []   # (time value, file name)
    steps = set()
    notes = []
    try:
        for path in dumps:
            try:
                for step, time, box, names, data in frames(path):
                    if step in steps:
                        print(f"dump2vtu: {path}: time step {step} again, skipped", file=sys.stderr)
                        continue
                    steps.add(step)
                    try:
                        pts = positions(names, data, box)
                    except DumpError as e:
                        raise DumpError(f"{path}: the frame of time step {step}: {e}") from None
                    point_data = {}
                    for i, n in enumerate(names):
                        point_data[n] = data[:, i].astype(np.int64) if n in INT_COLUMNS else data[:, i].copy()
                    cells = [("vertex", np.arange(len(pts), dtype=np.int64).reshape(-1, 1))]
                    vtu = f"{prefix}_{step}.vtu"
                    written.append((time if time is not None else step, vtu))
                    meshio.write(vtu, meshio.Mesh(pts, cells, point_data=point_data), file_format="vtu")
            except Truncated as e:
                notes.append(f"{e}: that frame is left out")
        if not written:
            raise DumpError("no complete frames in " + " ".join(dumps))
        pvd = prefix + ".pvd"
        base = os.path.dirname(os.path.abspath(pvd))
        with open(pvd, "w") as f:
            f.write('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n')
            for t, vtu in written:
                rel = os.path.relpath(os.path.abspath(vtu), base)
                f.write(f'    <DataSet timestep="{t!r}" part="0" file={xml.sax.saxutils.quoteattr(rel)}/>\n')
            f.write("  </Collection>\n</VTKFile>\n")
    except BaseException:
        for _, vtu in written:
            if os.path.exists(vtu):
                os.remove(vtu)
        raise
    return pvd, len(written), notes


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dumps", nargs="+", metavar="DUMP")
    ap.add_argument("-o", "--prefix", help="output prefix (default: the first dump's name)")
    a = ap.parse_args(argv)
    prefix = a.prefix or (a.dumps[0][:-3] if a.dumps[0].endswith(".gz") else a.dumps[0])
    try:
        pvd, n, notes = convert(a.dumps, prefix)
    except (DumpError, OSError, ValueError) as e:
        sys.exit(f"dump2vtu: ERROR: {e}; nothing written")
    for note in notes:
        print(f"dump2vtu: WARNING: {note}", file=sys.stderr)
    print(f"dump2vtu: {n} frames -> {pvd}")


if __name__ == "__main__":
    main()
