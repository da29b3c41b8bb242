"""The steady-state forces of the cutting examples (examples/cutting-2d-ti6al4v/steady.py) and their
standard error from 5 block means (seed003.block_error): known values for constant blocks, the
remainder left out, nan when a block would hold fewer than 2 samples, a correlated series whose
block error exceeds the error that independent samples would have, and steady.py's printed means
and errors on a forces.dat with a known answer.
Usage: python3 test_steady.py [SOURCE_DIR]   (default: the folder above this file)"""
import math
import os
import random
import re
import subprocess
import sys
import tempfile

root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
example = os.path.join(root, "examples", "cutting-2d-ti6al4v")
sys.path.insert(0, example)
from seed003 import block_error  # noqa: E402

fails = []


def check(cond, what):
    print(("ok    " if cond else "FAIL  ") + what)
    if not cond:
        fails.append(what)


# constant series: no error
check(block_error([7.0] * 50) == 0.0, "constant series: error 0")
# 5 blocks of 10 samples with means 1..5: sample deviation sqrt(2.5) / sqrt(5) = sqrt(0.5)
steps = [float(b + 1) for b in range(5) for _ in range(10)]
e = block_error(steps)
check(abs(e - math.sqrt(0.5)) < 1e-12, f"blocks 1..5: error {e:.15f} = sqrt(0.5)")
# 3 samples more at the end: left out (5 blocks of 10 again)
e3 = block_error(steps + [1000.0] * 3)
check(abs(e3 - math.sqrt(0.5)) < 1e-12, f"the remainder left out: {e3:.15f}")
check(math.isnan(block_error([1.0] * 9)), "fewer than 2 samples a block: nan")
# a strongly correlated series (AR(1), phi 0.995): the block error is several times the error of
# as many independent samples (sigma / sqrt(N)); for independent samples the two agree
rng = random.Random(3)
for phi, lo, hi in ((0.995, 3.0, 1e9), (0.0, 0.5, 1.6)):
    x, xs = 0.0, []
    for _ in range(20000):
        x = phi * x + rng.gauss(0.0, 1.0)
        xs.append(x)
    mu = sum(xs) / len(xs)
    naive = math.sqrt(sum((v - mu) ** 2 for v in xs) / (len(xs) - 1) / len(xs))
    r = block_error(xs) / naive
    check(lo < r < hi, f"AR(1) phi {phi}: block error / independent error {r:.2f} in ({lo}, {hi})")

# steady.py on a forces.dat with a known answer: 1001 lines over 1 mm of cut; the steady state is
# cut >= 0.1 mm (901 lines: 5 blocks of 180, the last line left out of the error); Fc 160 + 2 per
# block, Ft 40 throughout
with tempfile.TemporaryDirectory() as d:
    with open(os.path.join(d, "forces.dat"), "w") as f:
        f.write("# step time cut_mm Fc_N/mm Ft_N/mm Tmax_K Trake_K\n")
        for i in range(1001):
            cut = i / 1000.0
            k = (i - 100) // 180 if i >= 100 else 0
            fc = 160.0 + 2.0 * min(k, 4)
            f.write(f"{i * 10} {i * 1e-9} {cut} {fc} 40.0 900.0 800.0\n")
    run = subprocess.run([sys.executable, os.path.join(example, "steady.py")], cwd=d, capture_output=True, text=True)
    out = run.stdout
    print(out)
    check(run.returncode == 0, "steady.py runs")
    m = re.search(r"^sphcut\s+([\d.]+)\s+([\d.]+)\s+\(.*standard error of 5 block means ([\d.]+), ([\d.]+)\)", out, re.M)
    check(m is not None, "steady.py prints the means and the errors on the sphcut line")
    if m:
        fc_mean = (sum(160.0 + 2.0 * k for k in range(5)) * 180 + 168.0) / 901
        check(abs(float(m.group(1)) - fc_mean) < 0.051, f"Fc mean {m.group(1)} = {fc_mean:.2f}")
        check(float(m.group(2)) == 40.0, f"Ft mean {m.group(2)} = 40.0")
        check(abs(float(m.group(3)) - 2.0 * math.sqrt(0.5)) < 0.051, f"Fc error {m.group(3)} = {2 * math.sqrt(0.5):.2f}")
        check(float(m.group(4)) == 0.0, f"Ft error {m.group(4)} = 0.0")

if fails:
    sys.exit(f"FAILED: {len(fails)} check(s)")
print("all checks passed")
