"""tools/dump2vtu.py on damaged dumps (issue 50): a dump that ends inside a frame (plain or gzip,
cut inside an atom row or inside a frame's header) gives the .vtu files and a .pvd of the frames
before the cut, each equal to its frame, and a warning naming the cut frame; a binary file or a
value that is not a number stops with one line naming the file, the frame and the line, exit
status 1, no traceback, and leaves no .vtu or .pvd behind.
Usage: python test_dump2vtu.py DUMP2VTU  (run in an empty working folder; needs numpy and meshio)"""
import glob
import gzip
import os
import random
import re
import subprocess
import sys

try:
    import meshio
    import numpy as np
except ImportError as e:  # the test must not pass without them
    sys.exit(f"FAILED: {e}; install them with tools/python-deps.sh")

dump2vtu = sys.argv[1]
NATOMS, NFRAMES, STEPS = 1000, 5, [0, 100, 200, 300, 400]
NAMES = ["id", "type", "x", "y", "vx", "temperature"]
rng = random.Random(50)
fails = []


def check(cond, what):
    print(("ok    " if cond else "FAIL  ") + what)
    if not cond:
        fails.append(what)


# a dump custom of NFRAMES frames; rows[f][i]: the values of atom i in frame f; first[f]: the
# line number (from 1) of frame f's first atom row
lines, rows, first = [], [], []
for step in STEPS:
    lines += ["ITEM: TIMESTEP", str(step), "ITEM: NUMBER OF ATOMS", str(NATOMS), "ITEM: BOX BOUNDS mm mm pp",
              "-1e-3 4e-3", "-1e-3 1e-3", "-5e-6 5e-6", "ITEM: ATOMS " + " ".join(NAMES)]
    first.append(len(lines) + 1)
    frame = [[i + 1, 1 + i % 2, rng.uniform(0, 3e-3), rng.uniform(0, 3e-4), rng.uniform(-6, 6), rng.uniform(300, 900)]
             for i in range(NATOMS)]
    rows.append(frame)
    lines += [" ".join(str(v) for v in r) for r in frame]
text = "\n".join(lines) + "\n"


def run(name, data, suffix=""):
    """dump2vtu on a file of these contents (text or bytes), in a folder of its own: (exit status,
    stderr, the file, the .pvd's (time, file) pairs or None)"""
    os.makedirs(name, exist_ok=True)
    path = os.path.join(name, "dump.case" + suffix)
    with open(path, "wb" if isinstance(data, bytes) else "w") as f:
        f.write(data)
    r = subprocess.run([sys.executable, dump2vtu, path, "-o", os.path.join(name, "out")], capture_output=True, text=True)
    pvd = os.path.join(name, "out.pvd")
    listed = re.findall(r'timestep="([^"]+)" part="0" file="([^"]+)"', open(pvd).read()) if os.path.exists(pvd) else None
    print(f"info  {name}: exit {r.returncode}; stdout {r.stdout.strip()!r}; stderr {r.stderr.strip()!r}")
    check("Traceback" not in r.stderr, f"{name}: no Python traceback")
    return r.returncode, r.stderr.strip(), path, listed


def frames_equal(name, listed, nframes):
    """the .pvd lists the first nframes frames, each .vtu equal to its frame; no other .vtu is left"""
    check(listed is not None and [float(t) for t, _ in listed] == [float(s) for s in STEPS[:nframes]],
          f"{name}: the .pvd lists the {nframes} complete frames (time steps {STEPS[:nframes]})")
    vtus = sorted(glob.glob(os.path.join(name, "*.vtu")))
    check(len(vtus) == nframes, f"{name}: {len(vtus)} .vtu files = {nframes} (none of the cut frame)")
    for f, (_, vtu) in enumerate(listed or []):
        m = meshio.read(os.path.join(name, vtu))
        want = np.array(rows[f], dtype=float)
        same = len(m.points) == NATOMS and all(np.array_equal(np.asarray(m.point_data[c], dtype=float), want[:, k])
                                               for k, c in enumerate(NAMES))
        check(same, f"{name}: {vtu}: every column equals frame {f}'s")


# the whole dump: every frame (the reference for the cases below)
rc, err, path, listed = run("whole", text)
check(rc == 0 and err == "", f"whole: exit 0 ({rc}), no warning")
frames_equal("whole", listed, NFRAMES)

# plain text cut inside an atom row of the fourth frame (time step 300), its 500th row
cut = text.index("\n".join(lines[:first[3] - 1 + 500])) + len("\n".join(lines[:first[3] - 1 + 500])) - 4
rc, err, path, listed = run("plain_row", text[:cut])
check(rc == 0, f"plain_row: exit 0 ({rc}): the complete frames are converted")
check(f"{path}: line {first[3] + 499} (the frame of time step 300): the file ends inside the frame's atom rows" in err,
      f"plain_row: the warning names the file, line {first[3] + 499} and the cut frame (time step 300)")
frames_equal("plain_row", listed, 3)

# plain text cut inside the header of the third frame (time step 200): after NUMBER OF ATOMS
cut = len("\n".join(lines[:first[2] - 6])) + 1
rc, err, path, listed = run("plain_header", text[:cut])
check(rc == 0, f"plain_header: exit 0 ({rc})")
check(f"(the frame of time step 200): the file ends inside the frame's header" in err,
      "plain_header: the warning names the cut frame (time step 200)")
frames_equal("plain_header", listed, 2)

# gzip cut at 60 % of its bytes (the example of the issue: gzip -c dump | head -c N)
gz = gzip.compress(text.encode())
rc, err, path, listed = run("gzip_cut", gz[:int(0.6 * len(gz))], ".gz")
n = len(listed or [])
check(rc == 0 and 1 <= n < NFRAMES, f"gzip_cut: exit 0 ({rc}), {n} complete frames of {NFRAMES}")
check(n < NFRAMES and f"(the frame of time step {STEPS[n]}): the compressed file ends early" in err,
      f"gzip_cut: the warning names the cut frame (time step {STEPS[min(n, NFRAMES - 1)]})")
frames_equal("gzip_cut", listed, n)

# errors: exit 1, one line naming the file, the frame and the line, nothing written
def refused(name, data, what):
    rc, err, path, listed = run(name, data)
    check(rc == 1, f"{name}: exit 1 ({rc})")
    check(len(err.splitlines()) == 1 and err.startswith("dump2vtu: ERROR: ") and f"{path}: {what}" in err,
          f"{name}: one line with '{path}: {what}'")
    left = glob.glob(os.path.join(name, "out*"))
    check(not left, f"{name}: nothing written ({left})")


# a value that is not a number: frame 2 (time step 100), its 7th row
bad = list(lines)
bad[first[1] - 1 + 6] = bad[first[1] - 1 + 6].replace(" ", " 0.5x ", 1).rsplit(" ", 1)[0]
refused("not_a_number", "\n".join(bad) + "\n",
        f"line {first[1] + 6} (the frame of time step 100): '0.5x' is not a number")
# a row with a value missing: frame 3 (time step 200), its 10th row
bad = list(lines)
bad[first[2] - 1 + 9] = bad[first[2] - 1 + 9].rsplit(" ", 1)[0]
refused("short_row", "\n".join(bad) + "\n",
        f"line {first[2] + 9} (the frame of time step 200): 5 values for the 6 columns")
# binary bytes inside the second frame's rows: after its 3rd row
raw = ("\n".join(lines[:first[1] + 2]) + "\n").encode()
refused("binary", raw + bytes([0x8b, 0xff, 0x00, 0x1f]) * 50 + b"\n",
        f"line {first[1] + 3} (the frame of time step 100): not a text dump (byte 0x8b is not UTF-8 text)")
# a binary file from its first byte (a restart file given by mistake)
refused("binary_file", bytes([0x8b, 0xff, 0x00]) * 100, "line 1: not a text dump (byte 0x8b is not UTF-8 text)")

print(f"{len(fails)} failed" if fails else "all passed")
sys.exit(1 if fails else 0)
