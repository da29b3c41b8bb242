#!/usr/bin/env python3
"""sphcut - the mean thickness of the simulated chip of a 2D orthogonal cut, normal to the rake
face, over the steady part of the cut: comparable with the measured mean chip thickness of a
collected chip (e.g. hchip_avg of Klippel et al., Int J Adv Manuf Technol 135 (2024) 2871-2908,
doi:10.1007/s00170-024-14597-2).

Reads the text dump of examples/cutting-2d-ti6al4v (dump_sph: columns id, type, x, y, ..., role,
...; role 0 workpiece, 1 tool, 2 clamped).  In each frame:
  - the rake face is the line half a spacing in front of the foremost tool particles, with the
    direction of the rake angle (--rake, degrees; > 0 leans it back): s runs up the rake face, n
    normal to it, out of the tool into the chip.  The tool particles lie on the lattice at least
    half a spacing inside the face, so this line lies up to a spacing in front of the true face:
    the thickness, an area per length, does not depend on it (only where the band starts, by
    the spacing times sin(rake));
  - the chip is the workpiece material (role 0) above the original free surface y0 (the highest
    workpiece particle of the first frame, or --surface) in front of the rake face (n > -d/2);
  - in each band of the rake face, from s0 + lo h to s0 + hi h above the free surface (s0: where
    the rake face crosses y0; h: the uncut chip thickness, the depth of the tool's lowest particle
    below y0 rounded to the spacing, or --h), the chip's thickness is the area of its material in
    the band divided by the band's length: each particle covers dx^2 (the lattice spacing, the
    nearest-neighbour distance of the rigid tool particles, or --dx), a spacing along the rake
    face, of which its share in the band counts; in sub-bands of at least 2 spacings, the
    particles from the rake face outwards until a gap wider than 2 spacings (a chip that curls
    back into the band is not counted twice).  A frame whose chip does not reach the rake face in
    every sub-band (not yet formed there, or curled away), or that does not reach past the band
    (within 2 h of the rake face: a chip still growing into the band), is left out.
The area per length is the mean thickness over the band whatever the shape of the chip's free
side: a serrated chip gives the mean of its teeth and valleys, as a thickness measured on the
collected chip does; the distance to the outermost particle would give its teeth.  Near the
chip's root (the primary shear zone, up to about h above the surface) the band would cross the
bend from the free surface into the chip, and above the tool-chip contact the chip curls away
from the rake face and a band crosses it obliquely: the default band, 0.5-1.5 h above the surface,
lies between them in the quick cut (examples/cutting-2d-ti6al4v/README.md).
The frames are those whose cut length (the rake face's travel past the workpiece's right face,
x_face, the first frame's rightmost workpiece particle plus half a spacing; as in.cutting's
cut_mm at rake 0) is at least --from times the last frame's (default 0.3) and at least the length
that carries the first chip material past the band (n_frames 0 otherwise: an error).

Usage: python3 tools/chip_thickness.py DUMP [--rake DEG] [--from FRACTION] [--band LO HI]
                                         [--h M] [--surface M] [--dx M] [--json]
Prints the mean thickness and its standard deviation over the frames (the frame means) in um;
--json prints a JSON object (the dict chip_thickness() returns, without the per-frame lists).
Python: from chip_thickness import chip_thickness
        r = chip_thickness("dump.cutting", rake_deg=0.0, t_from=0.3)   # r["mean_um"], r["sd_um"], ...
Needs numpy.
"""
import argparse
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from dump2vtu import DumpError, frames  # noqa: E402

REQUIRED = ("x", "y", "role")


class ChipError(Exception):
    pass


def _columns(names, path, step):
    col = {n: i for i, n in enumerate(names)}
    missing = [c for c in REQUIRED if c not in col]
    if missing:
        raise ChipError(f"{path}: time step {step}: the dump has no column(s) {' '.join(missing)} "
                        f"(columns: {' '.join(names)}); write it with dump_sph ... x y ... role")
    return col


def _spacing(tool):
    """the lattice spacing: the median nearest-neighbour distance of the (rigid) tool particles"""
    if len(tool) < 2:
        raise ChipError("fewer than 2 tool particles (role 1): give --dx")
    d2 = ((tool[:, None, :] - tool[None, :, :]) ** 2).sum(axis=2)
    np.fill_diagonal(d2, np.inf)
    return float(np.median(np.sqrt(d2.min(axis=1))))


def chip_thickness(dump_path, rake_deg=0.0, t_from=0.3, band=(0.5, 1.5), h=None, surface=None, dx=None):
    """Mean chip thickness normal to the rake face over the steady frames of a 2D cutting dump.

    dump_path: a text dump (dump_sph of examples/cutting-2d-ti6al4v) with columns x, y and role;
    rake_deg: the rake angle in degrees; t_from: the steady part, frames whose cut length is at
    least this fraction of the last frame's; band: (lo, hi), the measuring band along the rake
    face, in units of h above the free surface; h, surface, dx: uncut chip thickness, the free
    surface's height and the particle spacing in m (None: from the dump, see the module's text).
    Returns a dict: mean_um, sd_um (the standard deviation of the frame means), sd_band_um (that
    of every band's value over the frames), nframes, h_um, dx_um, surface_um, band_um ((lo, hi)
    above the surface along the rake face), cut_mm (first and last frame used), and the lists
    steps, cut_mm_frames, thickness_um_frames.  Raises ChipError (bad input) or DumpError."""
    g = math.radians(rake_deg)
    tr = np.array([math.sin(g), math.cos(g)])      # up the rake face
    nr = np.array([-math.cos(g), math.sin(g)])     # out of the rake face, into the chip
    lo, hi = band
    if not (0.0 <= lo < hi):
        raise ChipError(f"band {lo} {hi}: needs 0 <= lo < hi (units of h above the free surface)")
    if not (0.0 <= t_from < 1.0):
        raise ChipError(f"from {t_from}: the steady part's start must be a fraction of the cut in [0, 1)")
    raw = {}    # step: (tool positions, workpiece positions); a step written twice (a continued
    y0 = xface = None    # run appends its first step again): the last frame
    for step, _time, _box, names, data in frames(dump_path):
        col = _columns(names, dump_path, step)
        if "z" in col and np.ptp(data[:, col["z"]]) > 0.0:
            raise ChipError(f"{dump_path}: time step {step}: a 3D dump (the z column varies): the chip thickness "
                            "is measured on 2D cuts")
        role = data[:, col["role"]]
        pos = data[:, [col["x"], col["y"]]]
        tool, work = pos[role == 1], pos[role == 0]
        if len(tool) == 0:
            raise ChipError(f"{dump_path}: time step {step}: no tool particles (role 1): the rake face is "
                            "placed from them")
        if len(work) == 0:
            raise ChipError(f"{dump_path}: time step {step}: no workpiece particles (role 0)")
        if dx is None:
            dx = _spacing(tool)
        if y0 is None:
            y0 = float(work[:, 1].max()) if surface is None else float(surface)
            xface = float(pos[role != 1][:, 0].max()) + 0.5 * dx
        raw[step] = (tool, work)
    if not raw:
        raise ChipError(f"{dump_path}: no frames")
    d = 0.5 * dx
    rows = []
    for step in sorted(raw):
        tool, work = raw[step]
        # the rake face: n = p.nr - c = 0, half a spacing in front of the foremost tool particles
        c = float((tool @ nr).max()) + d
        if h is None:
            # the tool's lowest particle lies at least half a spacing above the tip, less than 1.5
            # spacings on the lattice: h within a spacing below the true one (give --h)
            h = max(dx, y0 - (float(tool[:, 1].min()) - d))
        ytip = y0 - h
        # where the rake face crosses y (x on the line p.nr = c): x = (y sin g - c) / cos g
        xrake0 = (y0 * math.sin(g) - c) / math.cos(g)
        cut = xface - xrake0
        # s from the rake face's crossing of y0
        p0 = np.array([xrake0, y0])
        rel = work - p0
        s, n = rel @ tr, rel @ nr + c - p0 @ nr
        rows.append((step, cut, s, n, work[:, 1], ytip))
    lmax = max(r[1] for r in rows)
    s_lo, s_hi = lo * h, hi * h
    nb = max(1, int((s_hi - s_lo) / (2.0 * dx)))    # sub-bands of at least 2 spacings
    edges = np.linspace(s_lo, s_hi, nb + 1)
    steps, cuts, means, every = [], [], [], []
    for step, cut, s, n, y, _ in rows:
        if cut < t_from * lmax or cut <= 0.0:
            continue
        above = (y > y0) & (n > -d)
        # the chip must reach past the band (within 2 h of the rake face), or it only partly fills it
        if not (above & (s >= s_hi) & (n < 2.0 * h)).any():
            continue
        chip = above & (s + d > s_lo) & (s - d < s_hi)
        areas = []
        for b in range(nb):
            # each particle covers a spacing along the rake face: its share of the sub-band
            share = np.clip(np.minimum(s + d, edges[b + 1]) - np.maximum(s - d, edges[b]), 0.0, None)
            sel = chip & (share > 0.0)
            order = np.argsort(n[sel])
            nn, ww = n[sel][order], share[sel][order]
            if len(nn) == 0 or nn[0] > 3.0 * dx:
                # no material at the rake face here: the chip does not yet reach the band, or has left
                # the rake face (the chip's curl)
                areas = None
                break
            gaps = np.nonzero(np.diff(nn) > 2.0 * dx)[0]
            k = len(nn) if len(gaps) == 0 else gaps[0] + 1
            areas.append(float(ww[:k].sum()) * dx)
        if areas is None:
            continue
        steps.append(step)
        cuts.append(cut)
        means.append(sum(areas) / (s_hi - s_lo))
        every.extend(a / (edges[b + 1] - edges[b]) for b, a in enumerate(areas))
    if not means:
        raise ChipError(f"{dump_path}: no frame with chip material (role 0 above the free surface y0 = "
                        f"{y0 * 1e6:.1f} um, in front of the rake face) across the band {s_lo * 1e6:.1f}-"
                        f"{s_hi * 1e6:.1f} um above the surface along the rake face at cut lengths >= "
                        f"{t_from:g} x {lmax * 1e3:.4f} mm ({len(rows)} frames): a longer cut, a lower band "
                        "(--band) or a smaller --from")
    m = np.array(means)
    return {"mean_um": float(m.mean()) * 1e6,
            "sd_um": float(m.std(ddof=1)) * 1e6 if len(m) > 1 else float("nan"),
            "sd_band_um": float(np.std(every, ddof=1)) * 1e6 if len(every) > 1 else float("nan"),
            "nframes": len(m), "h_um": h * 1e6, "dx_um": dx * 1e6, "surface_um": y0 * 1e6,
            "band_um": (s_lo * 1e6, s_hi * 1e6), "cut_mm": (min(cuts) * 1e3, max(cuts) * 1e3),
            "rake_deg": rake_deg, "steps": steps, "cut_mm_frames": [c * 1e3 for c in cuts],
            "thickness_um_frames": [v * 1e6 for v in means]}


def main(argv=None):
    ap = argparse.ArgumentParser(description="mean chip thickness normal to the rake face over the steady cut "
                                 "(a 2D dump_sph dump of examples/cutting-2d-ti6al4v)")
    ap.add_argument("dump")
    ap.add_argument("--rake", type=float, default=0.0, help="rake angle, degrees (default 0)")
    ap.add_argument("--from", dest="t_from", type=float, default=0.3,
                    help="steady part: frames from this fraction of the last frame's cut length (default 0.3)")
    ap.add_argument("--band", type=float, nargs=2, default=(0.5, 1.5), metavar=("LO", "HI"),
                    help="band along the rake face, in uncut chip thicknesses above the free surface (default 0.5 1.5)")
    ap.add_argument("--h", type=float, help="uncut chip thickness, m (default: from the tool's lowest particle)")
    ap.add_argument("--surface", type=float, help="height of the free surface, m (default: the first frame's top)")
    ap.add_argument("--dx", type=float, help="particle spacing, m (default: from the tool particles)")
    ap.add_argument("--json", action="store_true", help="print a JSON object")
    a = ap.parse_args(argv)
    try:
        r = chip_thickness(a.dump, a.rake, a.t_from, tuple(a.band), a.h, a.surface, a.dx)
    except (ChipError, DumpError, OSError) as e:
        print(f"chip_thickness: ERROR: {e}", file=sys.stderr)
        return 1
    if a.json:
        print(json.dumps({k: v for k, v in r.items() if k not in ("steps", "cut_mm_frames", "thickness_um_frames")}))
    else:
        print(f"chip thickness {r['mean_um']:.1f} um (sd {r['sd_um']:.1f} um over {r['nframes']} frames, "
              f"{r['cut_mm'][0]:.3f}-{r['cut_mm'][1]:.3f} mm of cut; band {r['band_um'][0]:.1f}-{r['band_um'][1]:.1f} "
              f"um above the free surface along the rake face; h {r['h_um']:.1f} um, dx {r['dx_um']:.2f} um; "
              f"ratio to h {r['mean_um'] / r['h_um']:.2f})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
