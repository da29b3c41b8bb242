#!/usr/bin/env python3
"""examples/cutting-2d-ti6al4v/tool_fields.py on a constructed tool-fields.dat of known answer:
two rake facets, three edge facets round a rounded edge and two flank facets; the second-half
intervals averaged per facet (stresses plain, sliding speed and temperature weighted by the
contacts), the distances from the edge's mean centroid, the edge listed from the rake side (+) to
the flank side (-), and a file without an interval after step 0 refused.
usage: test_tool_fields.py REPO"""
import os
import subprocess
import sys
import tempfile

repo = sys.argv[1]
script = os.path.join(repo, "examples", "cutting-2d-ti6al4v", "tool_fields.py")
# facet: feature, centroid (x, y) in m; the edge's mean centroid is (0, 0)
facets = [(1, 0.0, 30e-6), (1, 0.0, 60e-6), (2, 0.0, 10e-6), (2, -5e-6, 0.0), (2, 5e-6, -10e-6),
          (3, -20e-6, -2e-6), (3, -40e-6, -4e-6)]
tmp = tempfile.mkdtemp()
path = os.path.join(tmp, "tool-fields.dat")


def row(f, k):
    feat, cx, cy = facets[f]
    # interval k: sigma_n (f+1) (k+1) 100 MPa, tau a quarter of it, v_s 1 + k, T 500 + 100 k, contacts k + 1
    sn = (f + 1) * (k + 1) * 1e8
    return [sn, 0.25 * sn, 1.0 + k, 500.0 + 100 * k, k + 1.0, 1e-6 * (f + 1), 1e-9 * k, 0, 0, 0, 1e-10, feat, cx, cy, 0.0]


with open(path, "w") as out:
    out.write("# Time-averaged data for fix tf\n# TimeStep Number-of-rows\n")
    for k, step in enumerate((0, 1000, 2000, 3000)):
        out.write(f"{step} {len(facets)}\n")
        for f in range(len(facets)):
            out.write(f"{f + 1} " + " ".join(repr(v) for v in row(f, k)) + "\n")
res = subprocess.run([sys.executable, script, path, "--out", os.path.join(tmp, "tf.png")],
                     capture_output=True, text=True)
assert res.returncode == 0, res.stderr
lines = [l.split() for l in res.stdout.splitlines() if l and not l.startswith("#") and not l.startswith("plot")
         and not l.startswith("(no")]
# intervals at steps >= 0.5 x 3000: 2000 and 3000 (k = 2, 3)
assert "steps 2000-3000" in res.stdout, res.stdout
names = [l[0] for l in lines]
assert names == ["rake"] * 2 + ["flank"] * 2 + ["edge"] * 3, names
byname = {}
for l in lines:
    byname.setdefault(l[0], []).append([float(x) for x in l[1:]])
for name, f_of in (("rake", (0, 1)), ("flank", (5, 6)), ("edge", (2, 3, 4))):
    for r, f in zip(byname[name], f_of):
        feat, cx, cy = facets[f]
        d = (cx * cx + cy * cy) ** 0.5 * 1e6
        if name == "edge" and cy < 0:
            d = -d
        assert abs(r[0] - d) < 0.006, (name, f, r[0], d)    # printed to 0.01 um
        sn = (f + 1) * (3 + 4) / 2 * 100.0    # mean over k = 2, 3 in MPa
        assert abs(r[1] - sn) < 1e-6 * sn and abs(r[2] - 0.25 * sn) < 1e-6 * sn, (name, r)
        vs = (3.0 * 3 + 4.0 * 4) / 7    # weighted by the contacts 3 and 4
        ts = (700.0 * 3 + 800.0 * 4) / 7
        assert abs(r[3] - vs) < 1e-3 and abs(r[4] - ts) < 0.1, (name, r)
        assert abs(r[5] - 3.5) < 1e-3, r
# the edge from the rake side round to the flank side
d = [r[0] for r in byname["edge"]]
assert d == sorted(d, reverse=True) and d[0] > 0 > d[-1], d
# a file with only step 0
with open(path, "w") as out:
    out.write(f"0 {len(facets)}\n")
    for f in range(len(facets)):
        out.write(f"{f + 1} " + " ".join(repr(v) for v in row(f, 0)) + "\n")
res = subprocess.run([sys.executable, script, path], capture_output=True, text=True)
assert res.returncode != 0 and "no averaging interval after step 0" in res.stderr, res.stderr
print("test_tool_fields: passed")
