"""The calibration tool (bench/validation/calibrate.py) on a tiny case on the CPU.
- bad input (dataset and options) stops with exit 2 and a message naming the row or keyword,
  nothing created or run;
- the hold-out split: K conditions or a fraction, deterministic, never every condition;
- synthetic recovery: "measured" forces made by sphcut itself at mu 0.35 (two conditions, coarse:
  spacing h / 3 and rn / 1, a cut of 1.2 h + 1 rn, no chip thickness: a few seconds a cut), then mu
  fitted from a start of 0.5 in [0.2, 0.6]: 0.35 is within the range the tool reports (measured:
  0.3501 +- 0.053, 0.2976-0.3719), that uncertainty is below 0.1 (a quarter of the box; 2x the
  measured), and the objective fell by more than
  its noise (the tool's table says so);
- resume: a calibration with a budget of 6 simulations, run again (no LAMMPS run), then with a
  budget of 20: it runs only the simulations not stored (counted through a wrapper), a fourth call
  none; the fitted set's file (fitted.args) given to validate.py finds its runs stored.
Usage: python3 test_calibration.py LMP SOURCE_DIR   (Debian's python3: numpy and scipy)"""
import json
import re
import os
import shutil
import subprocess
import sys
import tempfile
import time

from lmp_counter import lmp_counter    # this folder: a LAMMPS command that counts its runs

try:
    import scipy  # noqa: F401
except ImportError:
    print(f"{sys.executable} has no scipy: Debian's python3-scipy (tools/build-deps.sh installs it)")
    sys.exit(1)
lmp, root = sys.argv[1], sys.argv[2]
tool = os.path.join(root, "bench", "validation", "calibrate.py")
runner = os.path.join(root, "bench", "validation", "validate.py")
sys.path.insert(0, os.path.join(root, "bench", "validation"))
import calibrate  # noqa: E402

fails = []
t_start = time.time()


def check(cond, what):
    print(("ok    " if cond else "FAIL  ") + what, flush=True)
    if not cond:
        fails.append(what)


def call(script, *args):
    p = subprocess.run([sys.executable, script] + list(args), capture_output=True, text=True)
    return p.returncode, p.stdout + p.stderr


work = tempfile.mkdtemp(prefix="sphcut-calibration-")
HEADER = "test,vc_m_min,h_mm,Fc_N,sd_Fc_N,Ff_N,sd_Ff_N,rn_um\n"
good = os.path.join(work, "good.csv")
with open(good, "w") as f:
    f.write(HEADER + "A,318.5,0.05,100,3,70,3,20\nB,318.5,0.1,160,3,100,3,30\n")

# ---- bad input: exit 2, a message naming the row or keyword, nothing created
wrapper, lmp_calls = lmp_counter(work, lmp)


bad_data = [("missing column", HEADER.replace(",Ff_N,", ",", 1) + "A,318.5,0.05,100,3,3,20\n", "column(s) Ff_N missing"),
            ("negative", HEADER + "A,318.5,0.05,100,3,-70,3,20\n", "line 2: Ff_N -70 is negative"),
            ("NaN", HEADER + "A,318.5,0.05,NaN,3,70,3,20\n", "line 2: Fc_N is missing")]
bad_opts = [(["--fit", "mu=0.5:0.8"], "--fit mu=0.5:0.8: the start mu = 0.35 is outside the bounds"),
            (["--fit", "mu=0.8:0.2"], "--fit mu=0.8:0.2: lower bound 0.8 >= upper bound 0.2"),
            (["--fit", "mu=0.2:0.2"], "lower bound 0.2 >= upper bound 0.2"),
            (["--fit", "friction=0.1:0.9"], "--fit friction: unknown parameter"),
            (["--fit", "mu=0.2"], "--fit mu=0.2: expected NAME=LO:HI"),
            (["--fit", "mu=a:b"], "--fit mu=a:b: the bounds are not numbers"),
            ([], "--fit: give at least one"),
            (["--fit", "mu=0.2:0.8", "--param", "nope=3"], "--param nope: unknown parameter"),
            (["--fit", "mu=0.2:0.8", "--weights", "Fc=1,Fz=1"], "--weights Fz: unknown target"),
            (["--fit", "mu=0.2:0.8", "--weights", "Fc=-1"], "--weights Fc=-1: must be a finite number >= 0"),
            (["--fit", "mu=0.2:0.8", "--holdout", "2"], "--holdout 2: holds out 2 of 2 conditions"),
            (["--fit", "mu=0.2:0.8", "--holdout", "1.5"], "--holdout 1.5: a number of conditions"),
            (["--fit", "mu=0.2:0.8", "--budget", "1"], "--budget 1: less than one evaluation (2 conditions)")]
cases = [(n, t, ["--fit", "mu=0.2:0.8"], m) for n, t, m in bad_data] + [(" ".join(o), None, o, m) for o, m in bad_opts]
for name, text, opts, msg in cases:
    data = good
    if text is not None:
        data = os.path.join(work, "bad.csv")
        open(data, "w").write(text)
    out = os.path.join(work, "bad")
    rc, txt = call(tool, "--data", data, "--out", out, "--lmp", wrapper, *opts)
    check(rc == 2 and msg in txt and not os.path.exists(out) and lmp_calls() == 0,
          f"bad input ({name}): exit 2 with '{msg}', nothing run: rc {rc}: {txt.strip()[-150:]}")

# ---- the hold-out split
conds = [{"vc": v, "h": 0.1} for v in range(10)]
fit, held = calibrate.split_holdout(conds, "3", 1)
fit2, held2 = calibrate.split_holdout(conds, "0.3", 1)
check(len(held) == 3 and len(fit) == 7 and held == held2 and fit == fit2
      and sorted(c["vc"] for c in fit + held) == list(range(10)),
      f"hold-out: 3 (or 0.3) of 10 conditions, the same ones for the same seed: {[c['vc'] for c in held]}")
check(calibrate.split_holdout(conds, "0", 1) == (conds, []), "hold-out 0: every condition fitted")

# ---- synthetic data: sphcut at mu 0.35 (seed 003's set)
coarse = ["--per-h", "3", "--per-rn", "1", "--cut-h", "1.2", "--cut-rn", "1", "--no-chip", "--jobs", "2"]
db = os.path.join(work, "runs.sqlite")
truth = os.path.join(work, "truth")
t0 = time.time()
rc, txt = call(runner, "run", "--data", good, "--out", truth, "--db", db, "--lmp", lmp, *coarse)
print(f"truth: {time.time() - t0:.0f} s")
rows = [r.split(",") for r in open(os.path.join(truth, "table.csv")).read().splitlines()]
col = {c: i for i, c in enumerate(rows[0])}
synth = os.path.join(work, "synth.csv")
with open(synth, "w") as f:
    f.write(HEADER)
    for i, r in enumerate(rows[1:]):
        f.write(f"S{i},{r[col['vc']]},{r[col['h']]},{r[col['Fc_sim']]},{r[col['seFc_sim']]},"
                f"{r[col['Ft_sim']]},{r[col['seFt_sim']]},{r[col['rn_um']]}\n")
check(rc == 0 and len(rows) == 3, f"synthetic data: 2 conditions simulated at mu 0.35 (rc {rc})")
print(open(synth).read())
if fails:
    print(txt)
    sys.exit(1)

# the synthetic runs go to another database: the calibration does not see the truth's runs
out = os.path.join(work, "cal")
# (--init 3: the least-squares method, the default, starts from the best of a 3-point design: at
# this coarse resolution the forces are not monotonic in mu, and a local method from 0.5 alone
# finds a second minimum near 0.59)
base = ["--data", synth, "--out", out, "--lmp", wrapper, "--fit", "mu=0.2:0.6", "--param", "mu=0.5",
        "--init", "3"] + coarse


def calibration(budget):
    t = time.time()
    n0 = lmp_calls()
    rc, txt = call(tool, *base, "--budget", str(budget))
    print("\n".join(x for x in txt.splitlines() if not x.startswith("[")))
    return rc, txt, lmp_calls() - n0, time.time() - t


rc, txt, n, dt = calibration(6)
check(rc == 0 and n == 6 and "budget of 6 simulations spent" in txt,
      f"budget 6: 6 simulations (the 3 points of the design x 2 conditions) and the start's and best's "
      f"runs stored: {n} LAMMPS runs, {dt:.0f} s")
rc, txt, n, dt = calibration(6)
check(rc == 0 and n == 0, f"the same calibration again: no LAMMPS run ({n}, {dt:.0f} s)")
rc, txt, n, dt = calibration(20)
res = json.load(open(os.path.join(out, "calibration.json")))
check(rc == 0 and n == res["simulations_run"] and n <= 14 and res["simulations_reused"] == 6,
      f"budget 20: runs only what is not stored ({n} LAMMPS runs, {res['simulations_reused']} reused, {dt:.0f} s)")
rc, txt, n, dt = calibration(20)
check(rc == 0 and n == 0, f"the budget-20 calibration again: no LAMMPS run ({n}, {dt:.0f} s)")

# ---- recovery
fit = res["fit"][0]
mu, unc, (lo, hi) = fit["value"], fit["uncertainty"], fit["range"]
print(f"true mu 0.35, recovered {mu} +- {unc:.3g}, range {lo:.4g} - {hi:.4g} ({res['uncertainty_method']}), "
      f"{len(res['evaluations'])} evaluations")
check(lo <= 0.35 <= hi and abs(mu - 0.35) <= unc and 0 < unc <= 0.1,
      f"mu recovered within the reported uncertainty: {mu} +- {unc:.3g}, range {lo:.4g} - {hi:.4g} "
      "(true 0.35; the uncertainty under a quarter of the box, 0.1)")
ob = res["objective"]
table = open(os.path.join(out, "table.md")).read()
s, f = ob["start"]["fit"], ob["fitted"]["fit"]
check(s["J"] - f["J"] > s["noise_sim"] + f["noise_sim"] and "more than the simulation noise" in table,
      f"the objective fell by more than its noise: {s['J']:.3g} +- {s['noise_sim']:.2g} -> {f['J']:.3g}")
table = open(os.path.join(out, "table.md")).read()
check(table.count("\n| 318.5 |") == 2 and "| mu | 0.2 - 0.6 | 0.5 |" in table,
      "table.md: the fitted parameter and one row a condition")
# ---- a deadline that leaves no time: exit 3, nothing run, the same command resumes
n0 = lmp_calls()
rc, txt = call(tool, *[os.path.join(work, "cal-dl") if a == out else a for a in base], "--deadline", "1")
check(rc == 3 and "deadline reached" in txt and "the same command resumes" in txt and lmp_calls() == n0,
      f"--deadline 1: exit 3, nothing run (rc {rc}, {lmp_calls() - n0} runs)")

# ---- the other method, Nelder-Mead, reading the same database: the design's runs are reused
out_nm = os.path.join(work, "cal-nm")
t = time.time()
n0 = lmp_calls()
rc, txt = call(tool, *[out_nm if a == out else a for a in base], "--db", os.path.join(out, "runs.sqlite"),
               "--method", "nelder-mead", "--budget", "20")
n = lmp_calls() - n0
nm = json.load(open(os.path.join(out_nm, "calibration.json")))
fnm = nm["fit"][0]
print(f"nelder-mead: recovered {fnm['value']} +- {fnm['uncertainty']:.3g}, range {fnm['range'][0]:.4g} - "
      f"{fnm['range'][1]:.4g}, {len(nm['evaluations'])} evaluations, {n} LAMMPS runs, {time.time() - t:.0f} s")
check(rc == 0 and nm["simulations_reused"] >= 6 and n == nm["simulations_run"],
      f"nelder-mead on the same database: the design's runs reused ({nm['simulations_reused']} reused, {n} run)")
check(fnm["range"][0] <= 0.35 <= fnm["range"][1] and abs(fnm["value"] - 0.35) <= fnm["uncertainty"] <= 0.1,
      f"nelder-mead: mu recovered within its uncertainty: {fnm['value']} +- {fnm['uncertainty']:.3g}")
# the fitted set's file, given to validate.py, finds the fitted runs stored
fa = open(os.path.join(out, "fitted.args")).read().split()
rc, txt = call(runner, "run", "--data", synth, "--out", os.path.join(work, "check"), "--db",
               os.path.join(out, "runs.sqlite"), "--lmp", "false", *coarse, *fa)
check(rc == 0 and "2 stored" in txt and "0 to run" in txt, f"validate.py {' '.join(fa[-1:])}: both runs stored")

# fitted.lmp: the fitted values as in.cutting's index variables (-var params FILE), the provenance as comments
fl = open(os.path.join(out, "fitted.lmp")).read()
lv = {m.group(1): float(m.group(2)) for m in re.finditer(r"^variable\s+(\w+)\s+index\s+(\S+)$", fl, re.M)}
check(abs(lv.get("mu", -1) - fit["value"]) <= 1e-12 * abs(fit["value"]) and "# fitted on 2 conditions" in fl
      and "# command: python3 bench/validation/calibrate.py" in fl,
      f"fitted.lmp: mu {lv.get('mu')} as fitted ({fit['value']}), the conditions and the command as comments")
# the shipped Ti6Al4V set: the example's file and validate.py's --set calibrated hold the same values
sys.path.insert(0, os.path.join(root, "bench", "validation"))
import validate  # noqa: E402
ship = open(os.path.join(root, "examples", "cutting-2d-ti6al4v", "ti6al4v-calibrated.lmp")).read()
sv = {m.group(1): float(m.group(2)) for m in re.finditer(r"^variable\s+(\w+)\s+index\s+(\S+)$", ship, re.M)}
cal = validate.PARAM_SETS["calibrated"]
check(set(sv) == set(cal) and all(abs(sv[k] - cal[k]) <= 1e-12 * abs(cal[k]) for k in cal),
      f"ti6al4v-calibrated.lmp {sv} equals validate.py's --set calibrated {cal}")

print(f"test time {time.time() - t_start:.0f} s")
if fails:
    print(f"{len(fails)} checks failed")
    sys.exit(1)
shutil.rmtree(work)
print("all checks passed")
