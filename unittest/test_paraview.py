"""The cutting example's particle dump opens in ParaView, through tools/dump2vtu.py.

ParaView 5.11 (Debian bookworm) has no reader for LAMMPS dumps (printed below: its readers
named like one, and what OpenDataFile says to the dump), so the documented path is
tools/dump2vtu.py: a .vtu per frame and a .pvd index.  This test runs a short cut, converts
its dump, and opens the .pvd in ParaView's own Python (pvpython, headless): the time values
are the dump's time steps, and in every frame the points and every column of the dump, under
its name, equal the dump text parsed here independently.
Usage: python test_paraview.py LMP IN_FILE DUMP2VTU PVPYTHON  (run in an empty working folder)
       pvpython test_paraview.py --check PVD DUMP             (the ParaView side)"""
import os
import shutil
import subprocess
import sys


def parse_dump(path):
    """[(step, {column: list of floats})] with the rows sorted by id."""
    out = []
    with open(path) as f:
        lines = f.read().split("\n")
    i = 0
    while i < len(lines) and lines[i].strip():
        assert lines[i] == "ITEM: TIMESTEP", lines[i]
        step = int(lines[i + 1])
        assert lines[i + 2] == "ITEM: NUMBER OF ATOMS"
        n = int(lines[i + 3])
        assert lines[i + 4].startswith("ITEM: BOX BOUNDS")
        assert lines[i + 8].startswith("ITEM: ATOMS ")
        names = lines[i + 8].split()[2:]
        rows = [[float(v) for v in s.split()] for s in lines[i + 9:i + 9 + n]]
        rows.sort(key=lambda r: r[names.index("id")])
        out.append((step, {c: [r[k] for r in rows] for k, c in enumerate(names)}))
        i += 9 + n
    return out


def check_in_paraview(pvd, dump):
    import paraview.simple as ps
    from paraview import servermanager as sm
    from vtk.numpy_interface import dataset_adapter as dsa
    import numpy as np

    fails = []

    def check(cond, what):
        print(("ok    " if cond else "FAIL  ") + what)
        if not cond:
            fails.append(what)

    # what ParaView itself offers for a LAMMPS dump (information, not a requirement)
    pdm = sm.ProxyManager().SMProxyManager.GetProxyDefinitionManager()
    it = pdm.NewSingleGroupIterator("sources")
    it.GoToFirstItem()
    readers = []
    while not it.IsDoneWithTraversal():
        name = it.GetProxyName()
        if "Reader" in name and ("LAMMPS" in name.upper() or "DUMP" in name.upper()):
            readers.append(name)
        it.GoToNextItem()
    try:
        direct = ps.OpenDataFile(dump)
        direct = direct.GetXMLName() if direct else "nothing"
    except Exception as e:   # 5.11: "File not readable. No reader found for ..."
        direct = str(e).strip()
    print(f"info  {sm.vtkSMProxyManager.GetParaViewSourceVersion()}: LAMMPS dump readers {readers}; "
          f"OpenDataFile({os.path.basename(dump)}): {direct}")

    frames = parse_dump(dump)
    r = ps.OpenDataFile(pvd)
    check(r is not None and r.GetXMLName() == "PVDReader", "ParaView opens the .pvd with its PVDReader")
    times = list(r.TimestepValues)
    check(times == [float(s) for s, _ in frames],
          f"time values {times} = the dump's time steps {[s for s, _ in frames]}")
    for t, (step, cols) in zip(times, frames):
        r.UpdatePipeline(t)
        d = dsa.WrapDataObject(sm.Fetch(r))
        n = len(cols["id"])
        check(d.GetNumberOfPoints() == n, f"step {step}: {d.GetNumberOfPoints()} points = {n} atoms")
        names = list(d.PointData.keys())
        check(names == list(cols), f"step {step}: point arrays {names} = the dump's columns")
        if d.GetNumberOfPoints() != n or set(names) != set(cols):
            continue
        order = np.argsort(np.asarray(d.PointData["id"]))
        bad = [c for c in cols if not np.array_equal(np.asarray(d.PointData[c])[order], np.asarray(cols[c]))]
        check(not bad, f"step {step}: every array equals its dump column (exactly); differing: {bad}")
        pts = np.asarray(d.Points)[order]
        z = np.asarray(cols["z"]) if "z" in cols else np.zeros(n)
        check(np.array_equal(pts, np.column_stack([cols["x"], cols["y"], z])), f"step {step}: points = (x, y, z)")
    if frames and "role" in names and "vx" in names:
        # the values mean what they should (ParaView's arrays of the last frame): the tool's particles
        # (role 1) move with the tool at the cutting speed 318.5 m/min in -x (the dump's 6 digits)
        role = np.asarray(d.PointData["role"])
        vx = np.asarray(d.PointData["vx"])
        tool = role == 1
        check(0 < tool.sum() < len(role) and set(np.unique(role)) <= {0.0, 1.0, 2.0},
              f"last frame: role 1 (tool) on {int(tool.sum())} of {len(role)} particles, "
              f"roles {sorted(set(np.unique(role).tolist()))}")
        check(np.all(np.abs(vx[tool] + 318.5 / 60.0) < 1e-5),
              f"last frame: tool particles at vx = {vx[tool].min():.6g}..{vx[tool].max():.6g} m/s (-318.5/60)")
    return 1 if fails else 0


def main():
    if sys.argv[1] == "--check":
        sys.exit(check_in_paraview(sys.argv[2], sys.argv[3]))
    lmp, infile, dump2vtu, pvpython = sys.argv[1:5]
    if not shutil.which(pvpython):
        sys.exit(f"FAILED: no pvpython ('{pvpython}'): install Debian's python3-paraview "
                 "(tools/python-deps.sh does)")
    # a short cut at 11 particles across: 4 frames
    run = subprocess.run([lmp, "-in", infile, "-var", "ny", "11", "-var", "steps", "300", "-var", "dumpevery",
                          "100", "-var", "thermoevery", "100", "-log", "log.paraview"],
                         capture_output=True, text=True)
    if run.returncode != 0 or not os.path.exists("dump.cutting"):
        sys.exit("FAILED: LAMMPS run failed\n" + run.stdout[-3000:] + run.stderr[-3000:])
    conv = subprocess.run([sys.executable, dump2vtu, "dump.cutting", "-o", "vtu/cutting"],
                          capture_output=True, text=True)
    print(conv.stdout + conv.stderr, end="")
    if conv.returncode != 0:
        sys.exit("FAILED: dump2vtu.py")
    env = dict(os.environ)
    env.pop("PYTHONHOME", None)
    env.pop("PYTHONPATH", None)
    chk = subprocess.run([pvpython, "--force-offscreen-rendering", os.path.abspath(__file__), "--check",
                          "vtu/cutting.pvd", "dump.cutting"], capture_output=True, text=True, env=env)
    print(chk.stdout + chk.stderr[-3000:], end="")
    sys.exit(chk.returncode)


if __name__ == "__main__":
    main()
