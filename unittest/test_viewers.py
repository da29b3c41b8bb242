"""The cutting example's output opens in real viewers' readers: the particle dump in the OVITO
Python module (OVITO's own LAMMPS dump reader) with the SPH state under readable property
names, and the tool geometry in meshio (the VTK legacy reader, as ParaView reads it).
Usage: python test_viewers.py LMP IN_FILE  (run in an empty working folder)"""
import glob
import re
import subprocess
import sys

try:
    import meshio
    from ovito.io import import_file
except ImportError as e:  # the test must not pass without the readers
    sys.exit(f"FAILED: {e}; install them with tools/python-deps.sh")

lmp, infile = sys.argv[1], sys.argv[2]
# a short cut at 11 particles across: dumps every 500 steps, the tool every 2000
run = subprocess.run([lmp, "-in", infile, "-var", "ny", "11", "-var", "cut", "0.012e-3",
                      "-var", "dumpevery", "500", "-var", "thermoevery", "1000", "-log", "log.viewers"],
                     capture_output=True, text=True)
if run.returncode != 0:
    sys.exit("FAILED: LAMMPS run failed\n" + run.stdout[-3000:] + run.stderr[-3000:])
created = [int(n) for n in re.findall(r"Created (\d+) atoms", run.stdout)]
natoms = sum(created)
fails = []


def check(cond, what):
    print(("ok    " if cond else "FAIL  ") + what)
    if not cond:
        fails.append(what)


pipeline = import_file("dump.cutting")
nframes = pipeline.source.num_frames
check(nframes >= 3, f"OVITO reads {nframes} frames")
data = pipeline.compute(nframes - 1)
p = data.particles
check(p.count == natoms, f"OVITO particle count {p.count} = atoms created {natoms}")
names = set(p.keys())
want = {"Position", "Velocity", "Particle Identifier", "Particle Type", "density", "pressure", "sxx", "syy",
        "sxy", "vonmises", "plastic_strain", "plastic_strain_rate", "temperature", "role", "surface",
        "fcontact_x", "fcontact_y"}
check(want <= names, "readable properties present; missing: " + str(sorted(want - names)))
check(not any(n.startswith(("f_", "c_", "v_")) for n in names), "no f_ID[k]-style names: " + str(sorted(names)))
if not fails:
    import numpy as np
    T = np.asarray(p["temperature"])
    rho = np.asarray(p["density"])
    role = np.asarray(p["role"])
    ptype = np.asarray(p["Particle Type"])
    surf = np.asarray(p["surface"])
    check(np.all(T > 290.0) and np.all(T < 1878.0), f"temperature in (290, 1878) K: {T.min():.1f}..{T.max():.1f}")
    check(np.all(np.abs(rho[ptype == 1] / 4430.0 - 1.0) < 0.05), "workpiece density within 5 % of 4430")
    check(np.array_equal(role == 1, ptype == 2), "role 1 (tool) exactly on the tool particles (type 2)")
    check(0 < surf.sum() < 0.5 * len(surf), f"surface flag on {int(surf.sum())} of {len(surf)} particles")
    check(np.any(np.abs(np.asarray(p["fcontact_x"])) > 0.0), "contact forces on some particles")

vtk = sorted(glob.glob("tool-*.vtk"), key=lambda f: int(re.findall(r"\d+", f)[-1]))
check(len(vtk) >= 2, f"{len(vtk)} tool files")
if len(vtk) >= 2:
    first, last = meshio.read(vtk[0]), meshio.read(vtk[-1])
    nline = sum(len(c.data) for c in first.cells if c.type == "line")
    check(nline >= 4, f"meshio reads the 2D tool as {nline} line cells")
    import numpy as np
    nrm = np.concatenate(first.cell_data.get("normal", [np.zeros((0, 3))]))
    check(len(nrm) == nline and np.allclose(np.linalg.norm(nrm, axis=1), 1.0), "unit cell normals per line")
    # the tool tip is the lowest point: y = 0.3 mm - 0.1 mm (uncut chip thickness)
    ymin = first.points[:, 1].min()
    check(abs(ymin - 0.2e-3) < 1e-9, f"tool tip at y = {ymin * 1e3:.6f} mm (0.2 mm)")
    moved = first.points[:, 0].min() - last.points[:, 0].min()
    check(moved > 0.0, f"the tool moved {moved * 1e6:.2f} um in -x between the first and the last file")
sys.exit(1 if fails else 0)
