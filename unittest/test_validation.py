"""The validation runner (bench/validation/validate.py) on a tiny case: a dataset of two conditions
(three tests) at a coarse resolution on the CPU.
- the dataset's tests grouped by (vc, h) with the mean edge radius and the scatter
  sqrt(between^2 + mean within^2), checked against values computed here by hand;
- bad datasets and options stop with a message naming the line, column or option, nothing run;
- the mass scaling factor (vref / vc)^2 reaches the run as density x f and heat capacity / f;
- run: one condition (--limit 1), then both: the second call runs only the missing one, a third
  runs nothing (the runs database: the count of LAMMPS runs is checked);
- the table has one row per condition, its errors are simulated / measured - 1 of the stored
  results, the forces are those of forces.dat's steady part (recomputed here), and physical.
Usage: python3 test_validation.py LMP SOURCE_DIR"""
import csv
import json
import math
import os
import shutil
import sqlite3
import subprocess
import sys
import tempfile

from lmp_counter import lmp_counter    # this folder: a LAMMPS command that counts its runs

lmp, root = sys.argv[1], sys.argv[2]
runner = os.path.join(root, "bench", "validation", "validate.py")
sys.path.insert(0, os.path.join(root, "bench", "validation"))
import validate  # noqa: E402

fails = []


def check(cond, what):
    print(("ok    " if cond else "FAIL  ") + what, flush=True)
    if not cond:
        fails.append(what)


def call(*args):
    p = subprocess.run([sys.executable, runner] + list(args), capture_output=True, text=True)
    return p.returncode, p.stdout + p.stderr


work = tempfile.mkdtemp(prefix="sphcut-validation-")
data = os.path.join(work, "tiny.csv")
HEADER = "test,vc_m_min,h_mm,Fc_N,sd_Fc_N,Ff_N,sd_Ff_N,rn_um,sd_rn_um,hchip_avg_um,sd_hchip_um,status\n"
with open(data, "w") as f:
    f.write("# two conditions: 318.5 m/min with two tests, 100 m/min with one; one test failed\n")
    f.write(HEADER)
    f.write("T1,318.5,0.1,162.0,3.5,112.1,2.6,32.0,2.2,223.9,101.9,short\n")
    f.write("T2,318.5,0.1,158.0,3.9,104.9,3.0,28.0,4.6,-,-,short\n")
    f.write("T3,100,0.1,200.0,2.3,122.0,1.5,34.0,3.6,180.3,-,ok\n")
    f.write("T4,100,0.1,-7.8,29.5,-11.7,27.6,44.5,2.3,-,-,error\n")

# ---- the dataset grouped into conditions
conds = validate.conditions(validate.select(validate.load_dataset(data)))
check(len(conds) == 2, f"two conditions (the failed test left out): {len(conds)}")
c = {x["vc"]: x for x in conds}[318.5]
sfc = math.sqrt((162.0 - 160.0) ** 2 * 2 / 1 + (3.5 ** 2 + 3.9 ** 2) / 2)
check(c["n"] == 2 and abs(c["rn_um"] - 30.0) < 1e-12 and abs(c["Fc"] - 160.0) < 1e-12,
      f"318.5 m/min: 2 tests, mean edge 30 um, mean Fc 160: {c['n']} {c['rn_um']} {c['Fc']}")
check(abs(c["sFc"] - sfc) < 1e-12, f"scatter sqrt(between^2 + mean within^2) = {sfc:.6f}: {c['sFc']:.6f}")
check(c["hchip"] == 223.9 and c["shchip"] == 101.9, "chip thickness from the one test that has it")
g = validate.geometry(100.0, 0.1, 34.0, 10, 4, 5, 5, 318.5)
check(abs(g["massscale"] - (318.5 / 100) ** 2) < 1e-12, f"mass scaling (318.5/100)^2: {g['massscale']}")
dxg = g["H"] / (g["ny"] - 1)
check(abs(dxg - 34e-6 / 4) < 1e-15 and 0.3e-3 <= g["H"] < 0.3e-3 + dxg,
      f"spacing rn/4 (< h/10), height 3 h rounded up to the spacing: dx {dxg:.4e} H {g['H']:.4e} ny {g['ny']}")
a = validate.lmp_args(dict(g, input="x", steady_from=0.4), 0)
av = dict(zip(a[1::3], a[2::3]))
check(abs(float(av["rho"]) - 4430 * g["massscale"]) < 1e-6 and abs(float(av["cp"]) * g["massscale"] - 580) < 1e-9,
      f"the run gets rho x f and cp / f: {av['rho']} {av['cp']}")

a0, b0 = validate.linear_fit([0.02, 0.1, 0.2], [12.0, 28.0, 48.0])
check(abs(a0 - 8.0) < 1e-12 and abs(b0 - 200.0) < 1e-9, f"linear fit 8 + 200 h: {a0} {b0}")
# the measurements' own consistency: 10 + 1000 h at five h, one of them 50 % high (the robust line
# keeps to the other four: deviations 0, 0, 0, 0.5, 0), and a speed with two h (too few: not counted)
hs = [0.02, 0.04, 0.06, 0.08, 0.1]
ys = [10 + 1000 * h for h in hs]
ys[3] *= 1.5
a1, b1 = validate.theil_sen(hs, ys)
check(abs(a1 - 10.0) < 1e-9 and abs(b1 - 1000.0) < 1e-6, f"Theil-Sen line 10 + 1000 h past one outlier: {a1} {b1}")
mrows = [{"vc": 100.0, "h": h, "Fc_meas": y, "Ft_meas": y, "hchip_meas": None if k == 0 else y}
         for k, (h, y) in enumerate(zip(hs, ys))] + \
        [{"vc": 70.0, "h": h, "Fc_meas": 50.0, "Ft_meas": 50.0, "hchip_meas": 50.0} for h in (0.02, 0.04)]
mc = validate.measurement_consistency(mrows)
check(mc["Fc"][0] == 5 and abs(mc["Fc"][1] - 0.1) < 1e-12 and abs(mc["hchip"][1] - 0.5 / 4) < 1e-9,
      f"measurements about their own line: Fc 0.1 over 5, chip 0.125 over 4 (one without): {mc}")

# ---- bad input: a clear error, nothing run
bad = [("missing column", HEADER.replace(",Ff_N,", ",", 1) + "T1,318.5,0.1,162,3.5,32,2.2,-,-,ok\n",
        "column(s) Ff_N missing"),
       ("negative", HEADER + "T1,318.5,0.1,162,3.5,-112,2.6,32,2.2,-,-,ok\n", "line 2: Ff_N -112 is negative"),
       ("NaN", HEADER + "T1,318.5,0.1,162,3.5,112,2.6,nan,2.2,-,-,ok\n", "line 2: rn_um is missing"),
       ("text", HEADER + "T1,318.5,0.1,abc,3.5,112,2.6,30,2.2,-,-,ok\n", "line 2: Fc_N 'abc' is not a number"),
       ("short row", HEADER + "T1,318.5,0.1\n", "line 2: 3 fields, the header has 12")]
for name, text, msg in bad:
    p = os.path.join(work, "bad.csv")
    open(p, "w").write(text)
    rc, out = call("run", "--data", p, "--out", os.path.join(work, "bad"), "--lmp", "false")
    check(rc == 2 and msg in out and not os.path.exists(os.path.join(work, "bad")),
          f"bad dataset ({name}): exit 2 with '{msg}', nothing run: rc {rc}: {out.strip()[-160:]}")
for opts, msg in ((["--param", "nope=1"], "--param nope: unknown parameter"),
                  (["--param", "mu=x"], "--param mu=x: not a number"),
                  (["--set", "steel"], "--set steel: unknown parameter set"),
                  (["--hmin", "0.5"], "no test with status ok,short and h in [0.5, 0.2] mm")):
    rc, out = call("run", "--data", data, "--out", os.path.join(work, "bad"), "--lmp", "false", *opts)
    check(rc == 2 and msg in out and not os.path.exists(os.path.join(work, "bad")),
          f"bad option {' '.join(opts)}: '{msg}': rc {rc}: {out.strip()[-160:]}")

# ---- run the two conditions coarsely: the first call one, the second the other, the third none
out = os.path.join(work, "out")
coarse = ["--data", data, "--out", out, "--per-h", "4", "--per-rn", "1.4", "--cut-h", "1.6", "--cut-rn", "2",
          "--jobs", "2"]
wrapper, lmp_calls = lmp_counter(work, lmp)


rc, txt = call("run", *coarse, "--limit", "1", "--lmp", wrapper)
print(txt)
check(rc == 0 and lmp_calls() == 1, f"first call: one run (rc {rc}, {lmp_calls()} LAMMPS runs)")
rc, txt = call("run", *coarse, "--lmp", wrapper)
print(txt)
check(rc == 0 and lmp_calls() == 2 and "1 stored" in txt, f"second call: only the missing run ({lmp_calls()} in all)")
rc, txt = call("run", *coarse, "--lmp", wrapper)
check(rc == 0 and lmp_calls() == 2 and "0 to run" in txt, f"third call: nothing to run ({lmp_calls()} in all)")

# ---- the table against the database and forces.dat
rows = list(csv.DictReader(open(os.path.join(out, "table.csv"))))
check(len(rows) == 2 and all(r["status"] == "done" for r in rows), f"table: 2 rows, both done: {len(rows)}")
con = sqlite3.connect(os.path.join(out, "runs.sqlite"))
stored = {k: (json.loads(i), json.loads(r)) for k, i, r in con.execute("select key, inputs, results from runs")}
check(len(stored) == 2, f"database: 2 runs stored: {len(stored)}")
sys.path.insert(0, os.path.join(root, "examples", "cutting-2d-ti6al4v"))
from steady import read_rows  # noqa: E402
for r in rows:
    inputs, res = stored[r["key"]]
    for q, meas in (("Fc", "Fc_meas"), ("Ft", "Ft_meas")):
        err = float(r[q + "_err"])
        check(abs(err - (res[q] / float(r[meas]) - 1)) < 1e-12,
              f"vc {r['vc']}: {q} error {err:+.4f} = simulated / measured - 1")
    fr = read_rows(os.path.join(out, "runs", r["key"], "forces.dat"))
    lmax = max(x[1] for x in fr)
    sel = [x for x in fr if x[1] >= 0.4 * lmax]
    fc = sum(x[2] for x in sel) / len(sel)
    check(abs(fc - res["Fc"]) < 1e-9 * abs(fc) and lmax >= 0.98 * inputs["cut"] * 1e3,
          f"vc {r['vc']}: Fc {res['Fc']:.2f} is the steady mean of forces.dat over the last 60 % of {lmax:.3f} mm")
    check(50 < res["Fc"] < 400 and 5 < res["Ft"] < 300 and res["Fc"] > res["Ft"] * 0.5,
          f"vc {r['vc']}: physical forces Fc {res['Fc']:.1f} Ft {res['Ft']:.1f} N/mm")
    # the feature split: rake face + edge + flank is the whole force on the tool (decomp.dat's
    # lines every 100 steps against forces.dat's every 10: the means differ by sampling only)
    for q in ("Fc", "Ft"):
        parts = [res.get(f"{q}_{f}") for f in ("rake", "edge", "flank")]
        check(None not in parts and abs(sum(parts) - res[q]) < 0.05 * abs(res[q]) + 3 * res["se_" + q],
              f"vc {r['vc']}: {q} of rake + edge + flank {sum(p or 0 for p in parts):.1f} = {res[q]:.1f} N/mm")
    check(float(r["Fc_rake_sim"]) > float(r["Fc_flank_sim"]), f"vc {r['vc']}: the rake face carries more Fc "
          f"than the flank ({float(r['Fc_rake_sim']):.1f}, {float(r['Fc_flank_sim']):.1f})")
    f = inputs["massscale"]
    check(abs(f - max(1.0, (318.5 / float(r["vc"])) ** 2)) < 1e-12, f"vc {r['vc']}: mass scaling {f:.3f}")
md = open(os.path.join(out, "table.md")).read()
main_table = md.split("Where the simulated thrust sits")[0]
check("mean absolute error" in md and main_table.count("\n| 318.5 |") + main_table.count("\n| 100 |") == 2,
      "table.md: one row a condition and the mean absolute errors")
check("Where the simulated thrust sits" in md and md.count("\n| 318.5 | ") + md.count("\n| 100 | ") == 4,
      "table.md: the thrust by feature, one row a condition")

if fails:
    print(f"{len(fails)} checks failed")
    sys.exit(1)
shutil.rmtree(work)
print("all checks passed")
