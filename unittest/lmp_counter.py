"""A LAMMPS command that counts its runs, for the tests of the runners that must not rerun stored
simulations (test_validation.py, test_calibration.py): lmp_counter(work, lmp) writes the wrapper
script WORK/lmp.sh and returns (its path, a function giving the number of runs so far)."""
import os


def lmp_counter(work, lmp):
    counter = os.path.join(work, "lmp-calls")
    wrapper = os.path.join(work, "lmp.sh")
    with open(wrapper, "w") as f:
        f.write(f"#!/bin/sh\necho run >> {counter}\nexec {lmp} \"$@\"\n")
    os.chmod(wrapper, 0o755)
    return wrapper, lambda: len(open(counter).read().split()) if os.path.exists(counter) else 0
