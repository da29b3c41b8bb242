"""The chip thickness of a 2D cut (tools/chip_thickness.py) on constructed dumps of known answer:
a block of thickness t leaning on the rake face (rake 0 and 10 degrees; its lattice along the rake
face, and the axis-aligned lattice of the simulation), with the uncut workpiece and the tool's
particles, over frames of a moving tool; a serrated chip (a sawtooth free side) gives its mean;
a chip that curls back into the band is counted once; frames before the chip reaches the band are
left out; bad input (no chip, a missing column, no tool, a bad band) is refused with a clear
error, also by the command line.
Usage: python3 test_chip_thickness.py [SOURCE_DIR]   (default: the folder above this file)"""
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
tool_py = os.path.join(root, "tools", "chip_thickness.py")
sys.path.insert(0, os.path.join(root, "tools"))
from chip_thickness import ChipError, chip_thickness  # noqa: E402

fails = []


def check(cond, what):
    print(("ok    " if cond else "FAIL  ") + what)
    if not cond:
        fails.append(what)


DX, HU, HW, L = 10e-6, 100e-6, 300e-6, 1.2e-3    # spacing, uncut chip thickness, height, length [m]


def lattice(x0, x1, y0, y1):
    """sites of the axis-aligned lattice of spacing DX (origin 0) in [x0, x1] x [y0, y1]"""
    i = np.arange(math.ceil(x0 / DX - 1e-9), math.floor(x1 / DX + 1e-9) + 1)
    j = np.arange(math.ceil(y0 / DX - 1e-9), math.floor(y1 / DX + 1e-9) + 1)
    xx, yy = np.meshgrid(i * DX, j * DX)
    return np.column_stack([xx.ravel(), yy.ravel()])


def frame(xr, rake, chip, cut_started=True, xstart=3):
    """particles of one frame: the tool with its rake face crossing the tip's height at xr, the
    workpiece left of it (up to HW high; cut: only below the tip ahead of... the rake face), chip
    (positions, role 0).  Returns (positions, role)"""
    g = math.radians(rake)
    nr = np.array([-math.cos(g), math.sin(g)])
    ytip = HW - HU
    p0 = np.array([xr, ytip])
    # tool: lattice sites at least half a spacing inside the rake face, above the tip, 20 spacings
    # deep (on the lattice as in.cutting's: it moves with the tool, so shift by xr's fraction)
    shift = xr - round(xr / DX) * DX
    sites = lattice(xr - 5 * DX, xr + 25 * DX, ytip, ytip + 3 * HU) + [shift, 0.0]
    inside = ((sites - p0) @ nr <= -0.5 * DX) & (sites[:, 1] >= ytip + 0.5 * DX)
    tool = sites[inside]
    work = lattice(-2 * DX, L, -2 * DX, HW)
    if cut_started:
        # the cut material is gone: ahead of the rake face (its line at the height) above the tip
        ahead = ((work - p0) @ nr < 0.5 * DX) & (work[:, 1] > ytip)
        work = work[~ahead]
    pos = np.vstack([work, tool] + ([chip] if len(chip) else []))
    role = np.concatenate([np.where(work[:, 0] < 0, 2, 0), np.ones(len(tool)), np.zeros(len(chip))])
    return pos, role


def chip_block(xr, rake, thickness, s_from, s_to, phase=0.0, teeth=None, aligned=True):
    """a chip on the rake face (crossing the free surface HW at x of the face there): material from
    the face out to `thickness` (or, with teeth (amplitude, wavelength), thickness + a sawtooth of
    s), from s_from to s_to along the face above the free surface; its lattice along the face
    (aligned) or the axis-aligned one"""
    g = math.radians(rake)
    tr = np.array([math.sin(g), math.cos(g)])
    nr = np.array([-math.cos(g), math.sin(g)])
    xs = xr + HU * math.tan(g)          # the face at the free surface's height
    p0 = np.array([xs, HW])

    def local(s):
        if teeth is None:
            return np.full_like(s, thickness)
        amp, lam = teeth
        frac = ((s - phase) / lam) % 1.0
        return thickness + amp * (2.0 * frac - 1.0)     # sawtooth of mean `thickness`

    if aligned:
        s = np.arange(s_from + 0.5 * DX, s_to, DX) + phase % DX
        pts = []
        for sj in s:
            m = int(round(local(np.array([sj]))[0] / DX))
            for i in range(m):
                pts.append(p0 + sj * tr + (0.5 + i) * DX * nr)
        return np.array(pts)
    # the lattice's offset against the face changes from frame to frame (phase)
    sites = lattice(xs - 3 * HU, xs + 3 * HU, HW, HW + 5 * HU) + [(2.7 * phase) % DX, phase % DX]
    rel = sites - p0
    s, n = rel @ tr, rel @ nr
    keep = (s > s_from) & (s < s_to) & (n > 0) & (n < local(s)) & (sites[:, 1] > HW)
    return sites[keep]


def write_dump(path, frames_, extra_cols=True, drop=None):
    names = ["id", "type", "x", "y", "vx", "vy", "role"]
    if drop:
        names.remove(drop)
    with open(path, "w") as f:
        for k, (pos, role) in enumerate(frames_):
            f.write(f"ITEM: TIMESTEP\n{1000 * k}\nITEM: NUMBER OF ATOMS\n{len(pos)}\n")
            f.write("ITEM: BOX BOUNDS mm mm pp\n-1e-4 2e-3\n-1e-4 1e-3\n-5e-7 5e-7\n")
            f.write("ITEM: ATOMS " + " ".join(names) + "\n")
            for i, (p, r) in enumerate(zip(pos, role)):
                row = {"id": i + 1, "type": 2 if r == 1 else 1, "x": p[0], "y": p[1], "vx": 0.0, "vy": 0.0, "role": int(r)}
                f.write(" ".join(str(row[c]) for c in names) + "\n")


def cut_frames(rake, thickness, nframes=6, **kw):
    """frame 0: the tool xstart spacings right of the workpiece; then frames of the tool moved
    in -x with a chip on its rake face (cut 0.3-0.8 mm), the chip shifted along the face by
    a fraction of a spacing (or a tooth) from frame to frame"""
    xr0 = L + 3 * DX
    out = [frame(xr0, rake, np.zeros((0, 2)), cut_started=False)]
    for k in range(nframes):
        xr = L - 0.3e-3 - k * 0.1e-3
        lam = kw.get("teeth", (0, 1.0))[1]
        phase = (k / nframes) * (lam if "teeth" in kw else DX)
        chip = chip_block(xr, rake, thickness, 0.0, 3.0 * HU, phase=phase, **kw)
        out.append(frame(xr, rake, chip))
    return out


tmp = tempfile.mkdtemp(prefix="test_chip_thickness_")
T = 153e-6    # chip thickness, 15.3 spacings (not a whole number of them)
T_ROWS = round(T / DX) * DX    # the rows of a chip on the rake-face lattice: 150 um

for rake in (0.0, 10.0):
    for aligned in (True, False):
        path = os.path.join(tmp, f"block_{rake:g}_{aligned}.dump")
        write_dump(path, cut_frames(rake, T, aligned=aligned))
        r = chip_thickness(path, rake_deg=rake, t_from=0.45, h=HU)
        # the aligned chip holds round(T/DX) = 15 rows: 150 um; the axis-aligned one T on average
        want = T_ROWS if aligned else T
        tol = 0.1 * DX if aligned else 0.3 * DX
        lattice_kind = "rake-face lattice" if aligned else "axis-aligned lattice"
        check(abs(r["mean_um"] - want * 1e6) < tol * 1e6,
              f"rake {rake:g}, {lattice_kind}: chip {want * 1e6:.1f} um thick measures {r['mean_um']:.2f} um "
              f"(sd {r['sd_um']:.2f}, {r['nframes']} frames; within {tol * 1e6:.1f} um)")
        check(r["nframes"] == 5, f"rake {rake:g}, {lattice_kind}: the frames from 0.45 of the last frame's cut "
              f"(0.8 mm): 5 of 6 (got {r['nframes']}, cut {r['cut_mm'][0]:.3f}-{r['cut_mm'][1]:.3f} mm)")
        check(abs(r["dx_um"] - DX * 1e6) < 1e-6, f"rake {rake:g}: the spacing from the tool particles {r['dx_um']:.4f} um")
        if rake == 0.0 and aligned:
            # h from the tool's lowest particle (within a spacing below the true one)
            r2 = chip_thickness(path, rake_deg=rake, t_from=0.3)
            check(HU * 1e6 - DX * 1e6 - 1e-6 <= r2["h_um"] <= HU * 1e6 + 1e-6,
                  f"h from the tool's lowest particle: {r2['h_um']:.2f} um (true {HU * 1e6:.0f})")
            # the cut length of the last frame: the face at x = L - 0.8 mm, 0.805 mm past the workpiece's
            # face L + dx/2; the face placed from the tool particles lies within a spacing in front of it
            check(0.805 - DX * 1e3 - 1e-9 <= r["cut_mm"][1] <= 0.805 + 1e-9,
                  f"cut length of the last frame {r['cut_mm'][1]:.4f} mm (the face 0.805 mm past the workpiece, "
                  "within a spacing)")

# a serrated chip: sawtooth free side of +-40 um, wavelength 60 um (a band of 1 h holds 1.67 teeth:
# the single frame's mean is off, the frames' phases average it out)
path = os.path.join(tmp, "serrated.dump")
write_dump(path, cut_frames(0.0, T, nframes=12, teeth=(40e-6, 60e-6)))
r = chip_thickness(path, rake_deg=0.0, t_from=0.0, h=HU)
frames_um = r["thickness_um_frames"]
check(abs(r["mean_um"] - T * 1e6) < 0.3 * DX * 1e6,
      f"serrated chip (mean {T * 1e6:.0f} um, teeth +-40 um): {r['mean_um']:.2f} um (within 3 um), "
      f"frames {min(frames_um):.1f}-{max(frames_um):.1f} um, sd {r['sd_um']:.2f}")
check(r["sd_um"] > 1.0, f"the serrated chip's frames differ (sd {r['sd_um']:.2f} um > 1 um): the sd is the frames'")
# the distance to the outermost particle would give the teeth: more than the mean by far
check(max(frames_um) < (T + 40e-6) * 1e6 - 10.0, "the area measure does not give the teeth' height")

# a chip that curls back into the band: a second piece of material 3 h out from the rake face in
# the band is not counted
fr = cut_frames(0.0, T)
for k in range(1, len(fr)):
    pos, role = fr[k]
    xr = L - 0.3e-3 - (k - 1) * 0.1e-3
    curl = lattice(xr - 5 * HU, xr - 4 * HU, HW + 0.5 * HU, HW + 1.5 * HU)
    fr[k] = (np.vstack([pos, curl]), np.concatenate([role, np.zeros(len(curl))]))
path = os.path.join(tmp, "curl.dump")
write_dump(path, fr)
r = chip_thickness(path, rake_deg=0.0, t_from=0.3, h=HU)
check(abs(r["mean_um"] - T_ROWS * 1e6) < 0.1, f"a curled piece 3 h out in the band is not counted: {r['mean_um']:.2f} um")

# frames whose chip does not yet reach the band are left out: a chip 0.4 h long (below the band
# 0.5-1.5 h) in the frames before the last two
fr = [cut_frames(0.0, T, nframes=6)[0]]
for k in range(6):
    xr = L - 0.3e-3 - k * 0.1e-3
    top = 0.4 * HU if k < 4 else 3 * HU
    fr.append(frame(xr, 0.0, chip_block(xr, 0.0, T, 0.0, top)))
path = os.path.join(tmp, "growing.dump")
write_dump(path, fr)
r = chip_thickness(path, rake_deg=0.0, t_from=0.0, h=HU)
check(r["nframes"] == 2 and abs(r["mean_um"] - T_ROWS * 1e6) < 0.1,
      f"frames before the chip reaches the band are left out: {r['nframes']} frames (2), {r['mean_um']:.2f} um")


def refused(fn, needle, what):
    try:
        fn()
    except ChipError as e:
        check(needle in str(e), f"{what}: '{e}'")
        return
    check(False, f"{what}: no error")


# bad input: no chip at all, a missing column, no tool particles, a bad band or start
path = os.path.join(tmp, "nochip.dump")
write_dump(path, [frame(L + 3 * DX, 0.0, np.zeros((0, 2)), cut_started=False)] +
           [frame(L - 0.3e-3 - k * 1e-4, 0.0, np.zeros((0, 2))) for k in range(4)])
refused(lambda: chip_thickness(path, h=HU), "no frame with chip material", "no chip particles")
path = os.path.join(tmp, "norole.dump")
write_dump(path, cut_frames(0.0, T, nframes=2), drop="role")
refused(lambda: chip_thickness(path, h=HU), "the dump has no column(s) role", "a dump without the role column")
path = os.path.join(tmp, "notool.dump")
pos, role = cut_frames(0.0, T, nframes=1)[1]
write_dump(path, [(pos[role != 1], role[role != 1])])
refused(lambda: chip_thickness(path, h=HU), "no tool particles (role 1)", "a dump without tool particles")
path = os.path.join(tmp, "3d.dump")
with open(path, "w") as f:
    f.write("ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS mm mm pp\n0 1\n0 1\n0 1\n"
            "ITEM: ATOMS id x y z role\n1 0 0 0 0\n2 0 0 1e-5 1\n")
refused(lambda: chip_thickness(path, h=HU), "a 3D dump (the z column varies)", "a 3D dump")
path = os.path.join(tmp, "block_0_True.dump")
refused(lambda: chip_thickness(path, band=(1.5, 0.5)), "band 1.5 0.5: needs 0 <= lo < hi", "a reversed band")
refused(lambda: chip_thickness(path, t_from=1.0), "from 1.0: the steady part's start", "a start at the end of the cut")

# the command line: --json, and the error of a missing column with exit status 1
out = subprocess.run([sys.executable, tool_py, path, "--h", str(HU), "--json"], capture_output=True, text=True)
ok = out.returncode == 0
j = json.loads(out.stdout) if ok else {}
check(ok and abs(j["mean_um"] - T_ROWS * 1e6) < 0.1 and j["nframes"] == 6,
      f"command line --json: {out.stdout.strip()[:120]} {out.stderr.strip()[:200]}")
out = subprocess.run([sys.executable, tool_py, os.path.join(tmp, "norole.dump")], capture_output=True, text=True)
check(out.returncode == 1 and "no column(s) role" in out.stderr,
      f"command line, no role column: exit {out.returncode}, '{out.stderr.strip()[:160]}'")

print(f"{len(fails)} failure(s)" if fails else "all passed")
sys.exit(1 if fails else 0)
