"""The part test_milling.py and test_fsw.py share: run an example's LAMMPS input (stop with its
output's end if LAMMPS fails), the check() that prints and counts failures, and the example's output
file as rows of numbers without step 0 (the fix's tool fields are not set at step 0)."""
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


def rows_after_step0(path):
    rows = []
    with open(path) as f:
        for line in f:
            if not line.startswith("#") and line.strip():
                rows.append([float(x) for x in line.split()])
    return [r for r in rows if r[0] > 0]
