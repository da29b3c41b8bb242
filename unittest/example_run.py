"""The part test_milling.py and test_fsw.py share: run an example's LAMMPS input (stop with its
output's end if LAMMPS fails), the check() that prints and counts failures, the example's output
file as rows of numbers (all, or without step 0: the setup's row, no step taken, no interval of the
fix's tool fields averaged; its angle, from the tool fields' centroids, is checked apart), and the
checks of a spinning tool's torque and spindle power."""
import subprocess
import sys

fails = []


def run(args):
    p = subprocess.run(args, capture_output=True, text=True)
    out = p.stdout + p.stderr
    if p.returncode != 0:
        sys.exit("FAILED: LAMMPS run failed\n" + out[-4000:])
    return out


def check(cond, what):
    print(("ok    " if cond else "FAIL  ") + what)
    if not cond:
        fails.append(what)


def all_rows(path):
    rows = []
    with open(path) as f:
        for line in f:
            if not line.startswith("#") and line.strip():
                rows.append([float(x) for x in line.split()])
    return rows


def rows_after_step0(path):
    return [r for r in all_rows(path) if r[0] > 0]


def step0_row(path):
    """the row of step 0 (None if there is none)"""
    return next((r for r in all_rows(path) if r[0] == 0), None)


def check_spindle(rows, w, col_contacts, col_torque, col_power, min_contact, settle, unit):
    """the rows with contacts (at least min_contact); from settle steps after the first contact the
    torque (fix contact/tri-penalty element 53, on the particles) > 0, i.e. the cut's torque on the
    tool resists the rotation; spindle power (element 54) = torque * w to 1e-9.  The contact rows"""
    contact = [r for r in rows if r[col_contacts] > 0]
    check(len(contact) >= min_contact, f"{len(contact)} rows with contacts")
    first = contact[0][0] if contact else 0
    steady = [r for r in contact if r[0] >= first + settle]
    neg = [r for r in steady if not r[col_torque] > 0.0]
    check(steady and not neg, f"torque > 0 (the cut resists the rotation) in all {len(steady)} rows from {settle} "
          f"steps after the first contact (step {first:.0f}); {len(neg)} not; last {rows[-1][col_torque]:.4g} {unit}")
    err_p = max(abs(r[col_power] - r[col_torque] * w) / max(abs(r[col_torque] * w), 1e-30)
                for r in contact) if contact else 1.0
    check(err_p < 1e-9, f"spindle power = torque * rate: max relative error {err_p:.2e}")
    return contact
