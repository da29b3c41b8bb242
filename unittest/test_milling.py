"""The 2D milling example (examples/milling-2d-ti6al4v, issue 55) at the coarse spacing (dx 25 um),
down-milling from 1 degree before the entry, so that a tooth cuts a thick chip after about 1,300
steps; 3,000 steps in all.  Asserts the physics of the rotating cutter from milling.dat:
- the cutter's pose turns by rate * time: tooth 0's angle measured from the fix's turned facet
  (phi, from the tool-field centroid) equals phi0 + w t with w = vc / R, to 1e-8 degrees;
- the spindle torque (fix contact/tri-penalty element 53, the torque of the contact forces on the
  particles about the axis 0 0 -1) is > 0 once a tooth is in contact: the cut's torque on the
  cutter, its negative, resists the rotation;
- spindle power (element 54) = torque * w;
- the forces are finite and bounded; no particle starts in the tool's contact radius;
- plot.py's mechanistic model gives (-F_r, F_t) at phi 90 and reads the run's parameters;
- at step 0 (the setup's row of fix print) phi is the start phi0: the fix's array gives the
  centroids of the tool's pose there (they were zeros, on the CPU and under /kk); with a third
  argument "kokkos" also a short run with -sf kk, whose rows at steps 0 and 10 equal the CPU's.
Usage: python3 test_milling.py LMP EXAMPLE_DIR [kokkos]  (run in an empty working folder)"""
import math
import os
import subprocess
import sys

from example_run import all_rows, check, check_spindle, fails, rows_after_step0, run, step0_row  # this folder

lmp, exdir = sys.argv[1], sys.argv[2]
kokkos = len(sys.argv) > 3 and sys.argv[3] == "kokkos"
R, VC = 1.0e-3, 70.0
W = VC / 60.0 / R
args = [lmp, "-in", os.path.join(exdir, "in.milling"), "-var", "exdir", exdir, "-var", "dx", "25e-6",
        "-var", "mode", "down", "-var", "lead", "1", "-var", "steps", "3000", "-var", "R", repr(R),
        "-var", "vc", repr(VC), "-log", "log.milling"]
out = run(args)


check("start within the contact radius" not in out, "no particle starts within the tool's contact radius")
rows = rows_after_step0("milling.dat")
check(len(rows) >= 290, f"{len(rows)} rows of milling.dat")
phi0 = 180.0 - math.degrees(math.acos(1.0 - 0.5e-3 / R)) - 1.0
# 1. the pose: phi (from the fix's turned facet, wrapped) against phi0 + w t
err_fix = max(abs(((r[2] - r[3] + 180.0) % 360.0) - 180.0) for r in rows)
err_rate = max(abs(r[3] - (phi0 + math.degrees(W * r[1]))) for r in rows)
turned = rows[-1][3] - phi0
check(err_fix < 1e-8, f"the fix's tool turned by rate * time: max |phi - phi_rate| {err_fix:.2e} deg "
      f"over {turned:.3f} deg turned")
check(err_rate < 1e-8, f"phi_rate = phi0 + w t with w = vc/R = {W:.6g} rad/s: max error {err_rate:.2e} deg")
# the setup's row (step 0): the tool at its start, phi = phi0, from the fix's array (its centroids)
r0 = step0_row("milling.dat")
check(r0 is not None and abs(r0[2] - phi0) < 1e-8 and abs(r0[3] - phi0) < 1e-8,
      f"step 0: phi {r0[2] if r0 else None} = the start phi0 {phi0:.6f} deg (the fix's array at the setup)")
if kokkos:
    # the same input under /kk, 10 steps, a row every 10: the rows at step 0 and 10 as the CPU's
    os.makedirs("kk", exist_ok=True)
    kargs = args + ["-var", "printevery", "10", "-k", "on", "t", "2", "-sf", "kk", "-pk", "kokkos", "neigh", "full",
                    "newton", "off"]
    kargs[kargs.index("steps") + 1] = "10"
    kargs[kargs.index("-log") + 1] = "log.milling.kk"
    p = subprocess.run(kargs, capture_output=True, text=True, cwd="kk")
    check(p.returncode == 0, "the /kk run of 10 steps" + ("" if p.returncode == 0 else ": " + (p.stdout + p.stderr)[-2000:]))
    kr = all_rows(os.path.join("kk", "milling.dat")) if p.returncode == 0 else []
    cr = {r[0]: r for r in all_rows("milling.dat")}
    k0 = kr[0] if kr else None
    check(k0 is not None and k0[0] == 0 and abs(k0[2] - phi0) < 1e-8,
          f"/kk step 0: phi {k0[2] if k0 else None} = the start phi0 {phi0:.6f} deg")
    diff = max((abs(a - b) for r in kr for a, b in zip(r, cr.get(r[0], [math.inf] * len(r)))), default=math.inf)
    check(len(kr) == 2 and diff <= 1e-12,
          f"/kk rows at steps {[int(r[0]) for r in kr]} equal the CPU's: largest difference {diff:.2e}")
# 2. torque once a tooth is in contact, 3. power = torque * rate
check_spindle(rows, W, col_contacts=8, col_torque=6, col_power=7, min_contact=100, settle=300, unit="N m/mm")
# 4. finite, bounded forces (the model's peak at these conditions is about 200 N/mm)
fmax = max(math.hypot(r[4], r[5]) for r in rows)
check(all(math.isfinite(x) for r in rows for x in r[4:8]), "forces, torque and power finite")
check(fmax < 2000.0, f"largest |F| {fmax:.1f} N/mm < 2000")
check(rows[-1][5] > 0.0, f"down-milling near the entry pushes the cutter in +y: Fy {rows[-1][5]:.1f} N/mm")
# 5. the model of plot.py: at phi 90 (up-milling, ae = R: the tooth points along the feed) the force on
# the cutter is (-F_r, F_t), the torque R F_t; nothing outside the engagement; and plot.py reads the run
sys.path.insert(0, exdir)
import plot  # noqa: E402
v, K = plot.coefficients(72.0)
ft, fr = K["Kc"] * 0.08 + K["Ke"], K["Kr"] * 0.08 + K["Kre"]
fx, fy, tq = plot.model(90.0, R, 2, 0.08e-3, R, "up", K)
check(v == 70.0 and abs(fx + fr) < 1e-9 and abs(fy - ft) < 1e-9 and abs(tq - R * ft) < 1e-15,
      f"model at phi 90: Fx {fx:.3f} = -F_r {-fr:.3f}, Fy {fy:.3f} = F_t {ft:.3f} N/mm (fits at {v} m/min)")
check(plot.model(100.0, R, 2, 0.08e-3, 0.5e-3, "up", K) == (0.0, 0.0, 0.0), "model: no force outside the engagement")
pl = subprocess.run([sys.executable, os.path.join(exdir, "plot.py"), "-o", "milling.png"], capture_output=True, text=True)
check(pl.returncode == 0 and "engagement of a tooth 120.0..180.0" in pl.stdout,
      "plot.py reads milling.dat and the run's milling.params (down-milling): " + (pl.stdout + pl.stderr)[-300:])
sys.exit(1 if fails else 0)
