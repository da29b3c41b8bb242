#!/usr/bin/env python3
"""sphcut's validation runner: the 2D cut (examples/cutting-2d-ti6al4v/in.cutting) at the conditions
of a dataset of orthogonal cutting tests (cutting speed vc, uncut chip thickness h, the measured edge
radius of the insert), its steady forces and chip thickness against the measured ones.

    validate.py plan   [options]   the conditions, the runs they need, their size
    validate.py run    [options]   run what is missing (finished runs are kept in DB and never rerun)
    validate.py report [options]   table (markdown and CSV) and plots of simulated against measured

Every finished simulation is stored in an SQLite database (--db, default OUT/runs.sqlite) under the
hash of its inputs: an interrupted campaign resumes, another campaign with the same inputs reuses
the runs, and `sqlite3 OUT/runs.sqlite 'select * from runs'` shows what was run.

The dataset is a CSV file (lines starting with # are comments) with the columns vc_m_min, h_mm,
Fc_N, Ff_N, rn_um and optionally sd_Fc_N, sd_Ff_N, hchip_avg_um, sd_hchip_um, status, test; "-" or
an empty field is "not measured".  Forces are per mm of width (N/mm), as the 2D cut gives them.
Tests at the same vc and h are one condition: the simulation takes the mean measured edge radius of
its tests, and the condition's scatter is sqrt(sd between the tests^2 + mean sd within a test^2).

Low speeds: the step is set by the sound speed, the cut by vc, so a cut at 20 m/min takes 16x the
steps of one at 318.5 m/min.  The runner scales the workpiece's inertia (mass scaling, as explicit
FEM cutting codes do): density x f and heat capacity / f (rho cp, the conduction and the heating
stay those of the material), f = (vref / vc)^2, so every condition runs at the Mach number
vc / c of the cut at vref (318.5 m/min: f = 1), and each takes the same number of steps per mm of
cut.  The inertial stress rho f vc^2 stays below 1e-4 of the flow stress;  `--vref 0` turns it off
(`bench/validation/README.md` gives the measured effect on the forces).
"""
import argparse
import hashlib
import json
import math
import os
import re
import shlex
import signal
import sqlite3
import statistics
import subprocess
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
EXAMPLE = os.path.join(ROOT, "examples", "cutting-2d-ti6al4v")
sys.path.insert(0, EXAMPLE)
sys.path.insert(0, os.path.join(ROOT, "tools"))
from seed003 import block_error  # noqa: E402
from steady import read_rows  # noqa: E402

DATASET = os.path.join(HERE, "klippel2024_ti6al4v.csv")
INPUT = os.path.join(EXAMPLE, "in.cutting")

# Material and friction sets (in.cutting's -var names).  One set for every condition.  Each has
# hdx 1.5, the smoothing length that keeps the chip's free surface stable from 41 across (the
# example's README, "-var hdx")
PARAM_SETS = {
    # seed 003 (Afrasiabi et al., Appl. Sci. 11 (2021) 1020, doi:10.3390/app11031020), Table 1
    "seed003": {"jcA": 862e6, "jcB": 331e6, "jcC": 0.01, "jcn": 0.35, "jcm": 0.8, "Tmelt": 1878.0,
                "mu": 0.35, "hdx": 1.5},
    # identified by inverse SPH simulation of test V0060 of the same dataset: Klippel et al.,
    # CIRP J. Manuf. Sci. Technol. (2026), doi:10.1016/j.cirpj.2025.11.012
    "klippel2026": {"jcA": 852.1e6, "jcB": 338.9e6, "jcC": 0.02754, "jcn": 0.148, "jcm": 0.5961,
                    "Tmelt": 1836.0, "mu": 0.35, "hdx": 1.5},
    # seed003 with mu, jcA and jcm fitted by calibrate.py to 8 of this dataset's conditions
    # (examples/cutting-2d-ti6al4v/ti6al4v-calibrated.lmp says how; doc/calibration.md its errors)
    "calibrated": {"jcA": 921.4e6, "jcB": 331e6, "jcC": 0.01, "jcn": 0.35, "jcm": 0.8437, "Tmelt": 1878.0,
                   "mu": 0.4465, "hdx": 1.5},
}
# numeric -var inputs a parameter set or --param may set (in.cutting's names)
KNOWN_PARAMS = {"jcA", "jcB", "jcC", "jcn", "jcm", "Tmelt", "mu", "eta", "pfac", "dfac", "sfac",
                "hdx", "cfl", "pmin", "rake", "clearance", "land"}

REQUIRED = ("vc_m_min", "h_mm", "Fc_N", "Ff_N", "rn_um")
OPTIONAL = ("sd_Fc_N", "sd_Ff_N", "hchip_avg_um", "sd_hchip_um", "status", "test")
RHO0, CP0 = 4430.0, 580.0        # in.cutting's workpiece density and heat capacity


class InputError(Exception):
    """bad input: the message names the file, row or option"""


# ---------------------------------------------------------------- dataset
def _num(text, where, name, allow_missing):
    text = text.strip()
    if text in ("", "-", "nan", "NaN", "NA"):
        if allow_missing:
            return None
        raise InputError(f"{where}: {name} is missing")
    try:
        x = float(text)
    except ValueError:
        raise InputError(f"{where}: {name} '{text}' is not a number") from None
    if not math.isfinite(x):
        raise InputError(f"{where}: {name} '{text}' is not finite")
    if x < 0:
        raise InputError(f"{where}: {name} {text} is negative")
    return x


def load_dataset(path, statuses=("ok", "short")):
    """the tests of a dataset file with one of the status values (a file without a status column:
    every test): a list of dicts with floats (None where not measured)"""
    if not os.path.isfile(path):
        raise InputError(f"dataset {path}: no such file")
    header, tests = None, []
    with open(path, newline="") as f:
        for lineno, line in enumerate(f, 1):
            if line.startswith("#") or not line.strip():
                continue
            cells = [c.strip() for c in line.rstrip("\n").split(",")]
            if header is None:
                header = cells
                missing = [c for c in REQUIRED if c not in header]
                if missing:
                    raise InputError(f"dataset {path}: column(s) {', '.join(missing)} missing "
                                     f"(needs {', '.join(REQUIRED)})")
                continue
            where = f"dataset {path} line {lineno}"
            if len(cells) != len(header):
                raise InputError(f"{where}: {len(cells)} fields, the header has {len(header)}")
            row = dict(zip(header, cells))
            t = {"test": row.get("test") or f"line{lineno}", "status": row.get("status", "ok") or "ok",
                 "line": lineno}
            if "status" in row and t["status"] not in statuses:
                continue            # e.g. "error": the measurement failed, its values are not read
            for c in REQUIRED:
                t[c] = _num(row[c], where, c, False)
            for c in OPTIONAL[:4]:
                t[c] = _num(row[c], where, c, True) if c in row else None
            for c in ("vc_m_min", "h_mm", "rn_um"):
                if t[c] == 0:
                    raise InputError(f"{where}: {c} must be > 0")
            tests.append(t)
    if header is None:
        raise InputError(f"dataset {path}: no header line")
    return tests


def select(tests, hmin=0.02, hmax=0.2, vcs=None):
    out = [t for t in tests if hmin - 1e-12 <= t["h_mm"] <= hmax + 1e-12]
    if vcs:
        out = [t for t in out if any(abs(t["vc_m_min"] - v) < 1e-6 for v in vcs)]
    return out


def _mean_scatter(values, sds):
    """mean of the tests' means and the condition's scatter: sqrt(between^2 + mean within^2)"""
    n = len(values)
    mean = math.fsum(values) / n
    between2 = sum((x - mean) ** 2 for x in values) / (n - 1) if n > 1 else 0.0
    within = [s for s in sds if s is not None]
    within2 = sum(s * s for s in within) / len(within) if within else 0.0
    return mean, math.sqrt(between2 + within2)


def conditions(tests):
    """tests grouped by (vc, h): measured means and scatter, the mean edge radius"""
    groups = {}
    for t in tests:
        groups.setdefault((t["vc_m_min"], t["h_mm"]), []).append(t)
    out = []
    for (vc, h), ts in sorted(groups.items()):
        c = {"vc": vc, "h": h, "tests": [t["test"] for t in ts], "n": len(ts),
             "rn_um": math.fsum(t["rn_um"] for t in ts) / len(ts)}
        c["Fc"], c["sFc"] = _mean_scatter([t["Fc_N"] for t in ts], [t["sd_Fc_N"] for t in ts])
        c["Ft"], c["sFt"] = _mean_scatter([t["Ff_N"] for t in ts], [t["sd_Ff_N"] for t in ts])
        hc = [t for t in ts if t["hchip_avg_um"] is not None]
        if hc:
            c["hchip"], c["shchip"] = _mean_scatter([t["hchip_avg_um"] for t in hc],
                                                     [t["sd_hchip_um"] for t in hc])
        else:
            c["hchip"] = c["shchip"] = None
        out.append(c)
    return out


# ---------------------------------------------------------------- runs
def geometry(vc, h_mm, rn_um, per_h, per_rn, cut_h, cut_rn, vref):
    """the simulation's inputs for one condition (SI units for in.cutting)"""
    h, rn = h_mm * 1e-3, rn_um * 1e-6
    dx = min(h / per_h, rn / per_rn)
    H = max(3.0 * h, h + 3.0 * rn)                 # room below the edge's deformation zone
    ny = int(math.ceil(H / dx - 1e-9)) + 1
    H = (ny - 1) * dx
    cut = cut_h * h + cut_rn * rn
    f = max(1.0, (vref / vc) ** 2) if vref > 0 else 1.0
    # 12 significant digits: the same inputs (and run keys) wherever the means were summed
    return {k: float(f"{x:.12g}") if isinstance(x, float) else x for k, x in
            {"vc": vc, "h": h, "rn": rn, "H": H, "ny": ny, "cut": cut, "massscale": f}.items()}


def run_key(inputs):
    return hashlib.sha1(json.dumps(inputs, sort_keys=True).encode()).hexdigest()[:16]


def input_hash():
    with open(INPUT, "rb") as f:
        return hashlib.sha1(f.read()).hexdigest()[:12]


def plan_runs(conds, args, params):
    """a run per condition, keyed by its inputs (not by the input file's text: a run made with an
    earlier in.cutting is reused, and the report counts such runs; --rerun-stale reruns them)"""
    runs = []
    for c in conds:
        g = geometry(c["vc"], c["h"], c["rn_um"], args.per_h, args.per_rn, args.cut_h, args.cut_rn, args.vref)
        inputs = dict(g, **params, thermal=args.thermal, steady_from=args.steady_from)
        runs.append({"cond": c, "inputs": inputs, "key": run_key(inputs)})
    return runs


def estimate(inputs):
    """particles and steps of a run (for the plan; the log has the real figures)"""
    dx = inputs["H"] / (inputs["ny"] - 1)
    L = max(1.5 * inputs["cut"], inputs["cut"] + 5 * inputs["h"])      # in.cutting's -var length 0
    particles = (L / dx) * inputs["ny"]
    c = math.sqrt(113.8e9 / (3 * (1 - 2 * 0.35)) / (RHO0 * inputs["massscale"]))
    dt = 0.5 * inputs.get("hdx", 1.5) * dx / (c + inputs["vc"] / 60) / 1.45   # in contact (41 across: 1.45)
    steps = (inputs["cut"] + 3 * dx) / (inputs["vc"] / 60) / dt
    return particles, steps


def lmp_args(inputs, dumpevery):
    v = dict(inputs)
    v.pop("steady_from")
    f = v.pop("massscale")
    v["rho"], v["cp"] = RHO0 * f, CP0 / f
    v.update(length=0, dumpevery=dumpevery, xstart=1)
    out = []
    for k in sorted(v):
        out += ["-var", k, repr(v[k]) if isinstance(v[k], float) else str(v[k])]
    return out


class DB:
    def __init__(self, path):
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        self.con = sqlite3.connect(path, check_same_thread=False)
        self.lock = threading.Lock()
        self.con.execute("create table if not exists runs (key text primary key, inputs text, "
                         "results text, status text, wall_s real, finished text, host text)")
        self.con.commit()

    def get(self, key):
        with self.lock:
            r = self.con.execute("select inputs, results, status, wall_s from runs where key = ?",
                                 (key,)).fetchone()
        if r is None:
            return None
        return {"inputs": json.loads(r[0]), "results": json.loads(r[1]) if r[1] else None,
                "status": r[2], "wall_s": r[3]}

    def put(self, key, inputs, results, status, wall):
        with self.lock:
            self.con.execute("insert or replace into runs values (?, ?, ?, ?, ?, ?, ?)",
                             (key, json.dumps(inputs, sort_keys=True), json.dumps(results), status,
                              wall, time.strftime("%Y-%m-%d %H:%M:%S"), os.uname().nodename))
            self.con.commit()

    def count(self):
        with self.lock:
            return self.con.execute("select count(*) from runs").fetchone()[0]


DECOMP_EVERY = 100      # steps between lines of decomp.dat
FEATURES = ("rake", "edge", "flank")


def feature_forces(path, from_mm):
    """steady means of Fc and Ft [N/mm] carried by the rake face, the cutting edge and the flank
    (fix contact/tri-penalty vector 16-39 in decomp.dat: per feature the normal force x y, the
    friction force x y in N/m on the tool, then 4 counts); {} without the file"""
    if not os.path.exists(path):
        return {}
    sums, n = [0.0] * 6, 0
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            v = [float(x) for x in line.split()]
            if len(v) < 26 or v[1] < from_mm:
                continue
            for i in range(3):
                b = 2 + 8 * i
                sums[2 * i] += (v[b] + v[b + 2]) / 1000.0
                sums[2 * i + 1] += (v[b + 1] + v[b + 3]) / 1000.0
            n += 1
    if not n:
        return {}
    out = {}
    for i, f in enumerate(FEATURES):
        out["Fc_" + f], out["Ft_" + f] = sums[2 * i] / n, sums[2 * i + 1] / n
    return out


def analyse(rundir, inputs, wall):
    """steady means (cut >= steady_from of the cut) with the standard error of 5 block means,
    the chip thickness from the dump, the run's size and loop time"""
    rows = read_rows(os.path.join(rundir, "forces.dat"))
    cut_mm = inputs["cut"] * 1e3
    lmax = max(r[1] for r in rows)
    if lmax < 0.98 * cut_mm:
        raise RuntimeError(f"the run ended after {lmax:.4f} of {cut_mm:.4f} mm of cut")
    sel = [r for r in rows if r[1] >= inputs["steady_from"] * lmax]
    res = {"cut_mm": lmax, "samples": len(sel), "wall_s": wall, "input": input_hash()}
    for name, col in (("Fc", 2), ("Ft", 3), ("Trake", 5)):
        vals = [r[col] for r in sel]
        res[name] = sum(vals) / len(vals)
        res["se_" + name] = block_error(vals)
    with open(os.path.join(rundir, "log.cutting")) as f:
        log = f.read()
    m = re.findall(r"Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps with (\d+) atoms", log)
    if m:
        res["loop_s"] = sum(float(x[0]) for x in m)
        res["steps"] = sum(int(x[1]) for x in m)
        res["atoms"] = int(m[-1][2])
    res.update(feature_forces(os.path.join(rundir, "decomp.dat"), inputs["steady_from"] * lmax))
    dump = os.path.join(rundir, "dump.cutting")
    res["hchip"] = res["se_hchip"] = None
    if os.path.exists(dump):
        try:
            from chip_thickness import chip_thickness
            from chip_thickness import ChipError
            # the band 0.5-1.5 h above the free surface along the rake face (chip_thickness.py);
            # where the chip leaves the rake face below 1.5 h (thick chips curl early), 0.5-1 h
            for band in ((0.5, 1.5), (0.5, 1.0)):
                try:
                    ct = chip_thickness(dump, rake_deg=inputs.get("rake", 0.0), t_from=inputs["steady_from"],
                                        band=band, h=inputs["h"], dx=inputs["H"] / (inputs["ny"] - 1))
                    break
                except ChipError:
                    if band[1] == 1.0:
                        raise
            res["hchip_band_h"] = list(band)
            # the frame means are correlated over a few frames: the standard deviation over
            # sqrt(frames / 2) as their standard error
            res["hchip"], res["sd_hchip"] = ct["mean_um"], ct["sd_um"]
            res["se_hchip"] = ct["sd_um"] / math.sqrt(max(1.0, ct["nframes"] / 2.0))
            res["hchip_frames"] = ct["nframes"]
        except Exception as e:      # the forces stand; say why the thickness is missing
            res["hchip_error"] = f"{type(e).__name__}: {e}"
    return res


def run_campaign(args, runs, db):
    todo = []
    for r in runs:
        got = db.get(r["key"])
        stale = got and got["status"] == "done" and got["results"].get("input") != input_hash()
        if got and not (stale and args.rerun_stale) and \
                (got["status"] == "done" or (got["status"] == "failed" and not args.retry_failed)):
            continue
        todo.append(r)
    todo.sort(key=lambda r: -estimate(r["inputs"])[1])      # the longest first: no straggler at the end
    print(f"validate: {len(runs)} runs, {len(runs) - len(todo)} stored in {args.db}, {len(todo)} to run, "
          f"{args.jobs} at a time", flush=True)
    if not todo:
        return 0
    lmp = shlex.split(args.lmp or os.environ.get("LMP", "lmp"))
    t0 = time.time()
    deadline = t0 + args.deadline if args.deadline > 0 else None
    state = {"done": 0, "failed": 0, "best": None, "procs": set()}
    lock = threading.Lock()
    queue = list(todo)

    def one(r):
        rundir = os.path.join(args.out, "runs", r["key"])
        os.makedirs(rundir, exist_ok=True)
        # a dump frame about every 1/20 of the cut: the chip thickness over the steady part
        _, steps = estimate(r["inputs"])
        dumpevery = max(100, int(steps / 20 / 100) * 100) if args.chip else 0
        # the force on the tool by feature (rake face, cutting edge, flank: decomp.dat) beside
        # forces.dat: an output, not an input of the run's key
        cmd = lmp + ["-in", INPUT, "-log", "log.cutting", "-screen", "none"] + lmp_args(r["inputs"], dumpevery) \
            + ["-var", "decomp", str(DECOMP_EVERY)]
        with open(os.path.join(rundir, "command"), "w") as f:
            f.write(shlex.join(cmd) + "\n")
        ts = time.time()
        p = subprocess.Popen(cmd, cwd=rundir, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                             start_new_session=True)
        with lock:
            state["procs"].add(p)
        _, err = p.communicate()
        with lock:
            state["procs"].discard(p)
        wall = time.time() - ts
        if p.returncode < 0 or state.get("stopping"):
            return None                                  # killed at the deadline: not stored, rerun later
        try:
            if p.returncode != 0:
                tail, log = [], os.path.join(rundir, "log.cutting")
                if os.path.exists(log):
                    with open(log) as f:
                        tail = f.read().strip().splitlines()[-3:]
                raise RuntimeError(f"exit {p.returncode}: " + " | ".join(tail + err.decode()[-300:].splitlines()[-2:]))
            res = analyse(rundir, r["inputs"], wall)
            db.put(r["key"], r["inputs"], res, "done", wall)
            if not args.keep_dumps and os.path.exists(os.path.join(rundir, "dump.cutting")):
                os.remove(os.path.join(rundir, "dump.cutting"))
            return res
        except Exception as e:
            db.put(r["key"], r["inputs"], {"error": str(e)}, "failed", wall)
            return {"error": str(e)}

    def worker():
        while True:
            with lock:
                if not queue or (deadline and time.time() > deadline - args.min_left):
                    return
                r = queue.pop(0)
            res = one(r)
            with lock:
                if res is None:
                    continue
                c = r["cond"]
                if "error" in res:
                    state["failed"] += 1
                    msg = f"FAILED {res['error']}"
                else:
                    state["done"] += 1
                    e = max(abs(res["Fc"] / c["Fc"] - 1), abs(res["Ft"] / c["Ft"] - 1))
                    state["best"] = e if state["best"] is None else min(state["best"], e)
                    msg = (f"Fc {res['Fc']:.1f} (meas. {c['Fc']:.1f}), Ft {res['Ft']:.1f} (meas. {c['Ft']:.1f})"
                           + (f", hchip {res['hchip']:.1f} um" if res.get("hchip") else ""))
                n = state["done"] + state["failed"]
                el = time.time() - t0
                eta = el / n * (len(todo) - n)
                print(f"[{n}/{len(todo)}, {el:.0f} s, about {eta:.0f} s left] vc {c['vc']:g} h {c['h']:g} "
                      f"rn {c['rn_um']:.1f}: {msg}", flush=True)

    def watchdog():
        while any(t.is_alive() for t in threads):
            if deadline and time.time() > deadline:
                with lock:
                    state["stopping"] = True
                    for p in list(state["procs"]):
                        os.killpg(p.pid, signal.SIGTERM)
                return
            time.sleep(1)

    threads = [threading.Thread(target=worker) for _ in range(args.jobs)]
    for t in threads:
        t.start()
    w = threading.Thread(target=watchdog)
    w.start()
    for t in threads:
        t.join()
    w.join()
    left = len(todo) - state["done"] - state["failed"]
    print(f"validate: {state['done']} done, {state['failed']} failed, {left} left for the next call "
          f"({time.time() - t0:.0f} s)", flush=True)
    return 1 if state["failed"] else 0


# ---------------------------------------------------------------- report
def results_table(runs, db):
    rows = []
    for r in runs:
        got = db.get(r["key"])
        c = r["cond"]
        row = {"vc": c["vc"], "h": c["h"], "rn_um": c["rn_um"], "n": c["n"], "tests": " ".join(c["tests"]),
               "Fc_meas": c["Fc"], "sFc_meas": c["sFc"], "Ft_meas": c["Ft"], "sFt_meas": c["sFt"],
               "hchip_meas": c["hchip"], "shchip_meas": c["shchip"], "key": r["key"],
               "status": got["status"] if got else "missing"}
        res = got["results"] if got and got["status"] == "done" else None
        for q in ("Fc", "Ft", "hchip"):
            sim = res.get(q) if res else None
            row[q + "_sim"] = sim
            row["se" + q + "_sim"] = res.get("se_" + q) if res else None
            meas = row[q + "_meas"]
            row[q + "_err"] = (sim / meas - 1.0) if (sim is not None and meas) else None
        row["Trake_sim"] = res.get("Trake") if res else None
        for f in FEATURES:
            for q in ("Fc", "Ft"):
                row[f"{q}_{f}_sim"] = res.get(f"{q}_{f}") if res else None
        row["input"] = res.get("input") if res else None
        row["loop_s"] = res.get("loop_s") if res else None
        row["steps"] = res.get("steps") if res else None
        row["atoms"] = res.get("atoms") if res else None
        rows.append(row)
    return rows


def summary(rows):
    out = {}
    for q in ("Fc", "Ft", "hchip"):
        errs = [abs(r[q + "_err"]) for r in rows if r[q + "_err"] is not None]
        inside = [r for r in rows if r[q + "_err"] is not None
                  and abs(r[q + "_sim"] - r[q + "_meas"]) <= (r["s" + q + "_meas"] or 0.0)]
        out[q] = {"n": len(errs), "mae": sum(errs) / len(errs) if errs else None,
                  "max": max(errs) if errs else None, "within_scatter": len(inside)}
    return out


def linear_fit(xs, ys):
    """least squares y = a + b x: (a, b)"""
    n = len(xs)
    mx, my = math.fsum(xs) / n, math.fsum(ys) / n
    b = math.fsum((x - mx) * (y - my) for x, y in zip(xs, ys)) / math.fsum((x - mx) ** 2 for x in xs)
    return my - b * mx, b


def theil_sen(xs, ys):
    """the robust straight line y = a + b x: b the median of the pairwise slopes, a the median of
    y - b x (one outlier does not move it)"""
    slopes = [(ys[j] - ys[i]) / (xs[j] - xs[i]) for i in range(len(xs)) for j in range(i + 1, len(xs))
              if xs[j] != xs[i]]
    b = statistics.median(slopes)
    return statistics.median([y - b * x for x, y in zip(xs, ys)]), b


def measurement_consistency(rows):
    """per quantity: the mean absolute deviation of the measured values from a straight line in h
    fitted robustly (Theil-Sen) to the measurements of the same speed (speeds with 3 or more h) and
    the number of conditions: how far the measurements lie from a smooth trend of their own, about
    the closest a prediction that is smooth in h can come to them"""
    out = {}
    for q in ("Fc", "Ft", "hchip"):
        devs = []
        for vc in sorted({r["vc"] for r in rows}):
            rr = [r for r in rows if r["vc"] == vc and r[q + "_meas"]]
            if len({r["h"] for r in rr}) < 3:
                continue
            a, b = theil_sen([r["h"] for r in rr], [r[q + "_meas"] for r in rr])
            devs += [abs(r[q + "_meas"] / (a + b * r["h"]) - 1.0) for r in rr]
        out[q] = (len(devs), math.fsum(devs) / len(devs) if devs else None)
    return out


def edge_and_chip(rows):
    """per speed with 3 or more h: F = F_edge + k h for Fc and Ft, measured and simulated (the
    force at h -> 0, which the edge and the flank carry, and the slope, the chip's share on the rake
    face; the ratio of the slopes is the rake face's Ft / Fc)"""
    out = []
    for vc in sorted({r["vc"] for r in rows}):
        rr = [r for r in rows if r["vc"] == vc and r["Fc_sim"] is not None]
        if len({r["h"] for r in rr}) < 3:
            continue
        f = {}
        for q in ("Fc", "Ft"):
            for src in ("meas", "sim"):
                f[q, src] = linear_fit([r["h"] for r in rr], [r[f"{q}_{src}"] for r in rr])
        out.append((vc, len(rr), f))
    return out


def fmt(x, spec):
    return "-" if x is None else format(x, spec)


def write_report(args, runs, db, title):
    rows = results_table(runs, db)
    s = summary(rows)
    os.makedirs(args.out, exist_ok=True)
    cols = ["vc", "h", "rn_um", "n", "Fc_meas", "sFc_meas", "Fc_sim", "seFc_sim", "Fc_err", "Ft_meas", "sFt_meas",
            "Ft_sim", "seFt_sim", "Ft_err", "hchip_meas", "shchip_meas", "hchip_sim", "sehchip_sim", "hchip_err",
            "Trake_sim"] + [f"{q}_{f}_sim" for f in FEATURES for q in ("Fc", "Ft")] + \
           ["atoms", "steps", "loop_s", "status", "input", "key", "tests"]
    with open(os.path.join(args.out, "table.csv"), "w") as f:
        f.write(",".join(cols) + "\n")
        for r in rows:
            f.write(",".join("" if r[c] is None else str(r[c]) for c in cols) + "\n")
    lines = [f"# {title}", "",
             "Forces in N/mm of width; measured: mean of the condition's tests +- their scatter; "
             "simulated: steady mean +- standard error of 5 block means; error = simulated / measured - 1.", "",
             "| vc m/min | h mm | rn um | tests | Fc meas. | Fc sim. | err | Ft meas. | Ft sim. | err "
             "| hchip meas. um | hchip sim. um | err |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(
            f"| {r['vc']:g} | {r['h']:g} | {r['rn_um']:.1f} | {r['n']} "
            f"| {r['Fc_meas']:.1f} +- {r['sFc_meas']:.1f} | {fmt(r['Fc_sim'], '.1f')} +- {fmt(r['seFc_sim'], '.1f')} "
            f"| {fmt(r['Fc_err'] and 100 * r['Fc_err'], '+.0f')} % "
            f"| {r['Ft_meas']:.1f} +- {r['sFt_meas']:.1f} | {fmt(r['Ft_sim'], '.1f')} +- {fmt(r['seFt_sim'], '.1f')} "
            f"| {fmt(r['Ft_err'] and 100 * r['Ft_err'], '+.0f')} % "
            f"| {fmt(r['hchip_meas'], '.0f')} | {fmt(r['hchip_sim'], '.0f')} "
            f"| {fmt(r['hchip_err'] and 100 * r['hchip_err'], '+.0f')} % |")
    lines.append("")
    for q, name in (("Fc", "cutting force"), ("Ft", "thrust force"), ("hchip", "chip thickness")):
        v = s[q]
        if v["n"]:
            lines.append(f"- {name}: mean absolute error {100 * v['mae']:.1f} % over {v['n']} conditions, "
                         f"largest {100 * v['max']:.1f} %, {v['within_scatter']} within the measured scatter")
        else:
            lines.append(f"- {name}: no condition with both a measurement and a simulation")
    floor = measurement_consistency(rows)
    if all(floor[q][0] for q in floor):
        lines.append("- the measurements about a smooth trend of their own: a straight line in h per speed, fitted "
                     "robustly (Theil-Sen) to the measured values, misses them by "
                     + ", ".join(f"{100 * floor[q][1]:.1f} % ({name}, {floor[q][0]} conditions)" for q, name in
                                 (("Fc", "Fc"), ("Ft", "Ft"), ("hchip", "chip thickness")))
                     + " on average: about the closest a prediction smooth in h can come")
    done = [r for r in rows if r["status"] == "done"]
    stale = [r for r in done if r["input"] != input_hash()]
    if stale:
        lines.append(f"- {len(stale)} of {len(done)} runs were made with another version of in.cutting "
                     f"(its SHA-1 {', '.join(sorted({r['input'] or '?' for r in stale}))}, now {input_hash()}): "
                     "--rerun-stale runs them again")
    if done:
        loop = sum(r["loop_s"] or 0 for r in done)
        lines.append(f"- {len(done)} of {len(rows)} conditions simulated; loop time of the runs added up "
                     f"{loop:.0f} s")
    split = edge_and_chip(rows)
    if split:
        lines += ["", "Edge and chip: per speed, F = F0 + k h fitted over h (F0: the force at h -> 0, carried by "
                  "the edge and the flank; k in N/mm per mm of h; kt / kc: the rake face's Ft / Fc):", "",
                  "| vc m/min | conditions | Fc0 meas. | Fc0 sim. | kc meas. | kc sim. | Ft0 meas. | Ft0 sim. "
                  "| kt meas. | kt sim. | kt / kc meas. | kt / kc sim. |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for vc, n, f in split:
            lines.append(f"| {vc:g} | {n} | {f['Fc', 'meas'][0]:.0f} | {f['Fc', 'sim'][0]:.0f} | {f['Fc', 'meas'][1]:.0f} "
                         f"| {f['Fc', 'sim'][1]:.0f} | {f['Ft', 'meas'][0]:.0f} | {f['Ft', 'sim'][0]:.0f} "
                         f"| {f['Ft', 'meas'][1]:.0f} | {f['Ft', 'sim'][1]:.0f} "
                         f"| {f['Ft', 'meas'][1] / f['Fc', 'meas'][1]:.2f} | {f['Ft', 'sim'][1] / f['Fc', 'sim'][1]:.2f} |")
    feat = [r for r in rows if r.get("Ft_rake_sim") is not None]
    if feat:
        lines += ["", "Where the simulated thrust sits: the steady Ft [N/mm] on the rake face, the cutting edge and "
                  "the flank (fix contact/tri-penalty's decomposition, decomp.dat) beside the measured Ft and the "
                  "deficit (measured - simulated):", "",
                  "| vc m/min | h mm | Ft rake | Ft edge | Ft flank | Ft sim. | Ft meas. | deficit |",
                  "|---|---|---|---|---|---|---|---|"]
        for r in feat:
            lines.append(f"| {r['vc']:g} | {r['h']:g} | {r['Ft_rake_sim']:.1f} | {r['Ft_edge_sim']:.1f} "
                         f"| {r['Ft_flank_sim']:.1f} | {fmt(r['Ft_sim'], '.1f')} | {r['Ft_meas']:.1f} "
                         f"| {fmt(r['Ft_sim'] is not None and r['Ft_meas'] - r['Ft_sim'] or None, '.1f')} |")
    with open(os.path.join(args.out, "table.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))
    try:
        plots(args.out, rows, title)
    except ImportError:
        print("validate: matplotlib not found: no plots (Debian's /usr/bin/python3 has it)")
    return rows, s


def plots(out, rows, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = [r for r in rows if r["Fc_sim"] is not None]
    if not rows:
        return
    fig, axs = plt.subplots(1, 3, figsize=(15, 4.8))
    for ax, q, unit in zip(axs, ("Fc", "Ft", "hchip"), ("N/mm", "N/mm", "um")):
        rr = [r for r in rows if r[q + "_sim"] is not None and r[q + "_meas"] is not None]
        if not rr:
            ax.set_visible(False)
            continue
        for vc in sorted({r["vc"] for r in rr}):
            sub = [r for r in rr if r["vc"] == vc]
            ax.errorbar([r[q + "_meas"] for r in sub], [r[q + "_sim"] for r in sub],
                        xerr=[r["s" + q + "_meas"] or 0 for r in sub],
                        yerr=[r["se" + q + "_sim"] or 0 for r in sub], fmt="o", capsize=2,
                        label=f"vc {vc:g} m/min")
        lim = max(max(r[q + "_meas"] for r in rr), max(r[q + "_sim"] for r in rr)) * 1.1
        ax.plot([0, lim], [0, lim], "k-", lw=0.8)
        ax.fill_between([0, lim], [0, 0.85 * lim], [0, 1.15 * lim], color="0.9", label="+-15 %")
        ax.set_xlim(0, lim)
        ax.set_ylim(0, lim)
        ax.set_xlabel(f"measured {q} [{unit}]")
        ax.set_ylabel(f"simulated {q} [{unit}]")
        ax.legend(fontsize=7)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "parity.png"), dpi=110)
    plt.close(fig)
    fig, axs = plt.subplots(1, 2, figsize=(12, 4.5))
    for ax, xq, xl in zip(axs, ("vc", "h"), ("cutting speed vc [m/min]", "uncut chip thickness h [mm]")):
        for q, mk in (("Fc", "o"), ("Ft", "s"), ("hchip", "^")):
            rr = [r for r in rows if r[q + "_err"] is not None]
            if not rr:
                continue
            ax.errorbar([r[xq] * (1.0 + (0.01 if q == "Ft" else 0.0)) for r in rr],
                        [100 * r[q + "_err"] for r in rr],
                        yerr=[100 * (r["s" + q + "_meas"] or 0) / r[q + "_meas"] for r in rr],
                        fmt=mk, capsize=2, label=f"{q} (bars: measured scatter)")
        ax.axhline(0, color="k", lw=0.8)
        ax.set_xlabel(xl)
        ax.set_ylabel("simulated / measured - 1 [%]")
        ax.legend(fontsize=8)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "errors.png"), dpi=110)
    plt.close(fig)


# ---------------------------------------------------------------- command line
def name_value(kv, option, known, expected="NAME=VALUE", noun="parameter"):
    """an option's NAME=VALUE argument as (name, float): the name one of known, the value a number;
    an InputError names the option"""
    if "=" not in kv:
        raise InputError(f"{option} {kv}: expected {expected}")
    k, v = kv.split("=", 1)
    if k not in known:
        raise InputError(f"{option} {k}: unknown {noun} (known: {', '.join(known)})")
    try:
        return k, float(v)
    except ValueError:
        raise InputError(f"{option} {k}={v}: not a number") from None


def parse_params(args):
    if args.set not in PARAM_SETS:
        raise InputError(f"--set {args.set}: unknown parameter set (known: {', '.join(sorted(PARAM_SETS))})")
    p = dict(PARAM_SETS[args.set])
    for kv in args.param or []:
        k, p[k] = name_value(kv, "--param", sorted(KNOWN_PARAMS))
        if not math.isfinite(p[k]):
            raise InputError(f"--param {kv}: not finite")
    return p


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("command", choices=("plan", "run", "report"))
    ap.add_argument("--data", default=DATASET, help="dataset CSV (default: the Klippel et al. 2024 Ti6Al4V tests)")
    ap.add_argument("--out", default="validation-out", help="output folder (runs/, table, plots)")
    ap.add_argument("--db", help="SQLite database of the runs (default OUT/runs.sqlite)")
    ap.add_argument("--status", default="ok,short", help="tests of these status values (default ok,short)")
    ap.add_argument("--hmin", type=float, default=0.02, help="smallest h [mm] (default 0.02)")
    ap.add_argument("--hmax", type=float, default=0.2, help="largest h [mm] (default 0.2)")
    ap.add_argument("--vc", help="only these speeds [m/min], comma-separated")
    ap.add_argument("--limit", type=int, default=0, help="only the first N conditions")
    ap.add_argument("--set", default="seed003", help="material and friction set: " + ", ".join(PARAM_SETS))
    ap.add_argument("--param", action="append", help="NAME=VALUE: change one input of the set (e.g. mu=0.5)")
    ap.add_argument("--per-h", type=float, default=10.0, help="particle spacing <= h / this (default 10)")
    ap.add_argument("--per-rn", type=float, default=4.0, help="particle spacing <= edge radius / this (default 4)")
    ap.add_argument("--cut-h", type=float, default=5.0, help="cut length = CUT_H h + CUT_RN rn (default 5)")
    ap.add_argument("--cut-rn", type=float, default=5.0, help="(default 5)")
    ap.add_argument("--steady-from", type=float, default=0.4, help="steady means over the cut after this fraction")
    ap.add_argument("--vref", type=float, default=318.5,
                    help="mass scaling to the Mach number of this speed [m/min] (0: none)")
    ap.add_argument("--thermal", type=int, default=1, choices=(0, 1), help="1: with conduction (default)")
    ap.add_argument("--no-chip", dest="chip", action="store_false", help="no dump, no chip thickness")
    ap.add_argument("--keep-dumps", action="store_true", help="keep each run's dump.cutting")
    ap.add_argument("--lmp", help="LAMMPS command with its arguments (default $LMP), e.g. "
                    "'lmp_sphcut -k on g 1 -sf kk -pk kokkos neigh full newton off' or 'mpirun -np 4 lmp'")
    ap.add_argument("--jobs", type=int, default=1, help="runs at a time (default 1)")
    ap.add_argument("--deadline", type=float, default=0, help="seconds: start no run after DEADLINE - MIN_LEFT, "
                    "stop the running ones at DEADLINE (they are rerun by the next call)")
    ap.add_argument("--min-left", type=float, default=60, help="(default 60 s)")
    ap.add_argument("--retry-failed", action="store_true", help="run failed runs again")
    ap.add_argument("--rerun-stale", action="store_true",
                    help="run again the runs stored from another version of in.cutting")
    ap.add_argument("--title", help="title of the table and plots")
    args = ap.parse_args(argv)
    if args.jobs < 1:
        ap.error(f"--jobs {args.jobs}: must be >= 1")
    for name in ("per_h", "per_rn", "cut_h"):
        if not getattr(args, name) > 0:
            ap.error(f"--{name.replace('_', '-')} {getattr(args, name)}: must be > 0")
    if not 0 <= args.steady_from < 1:
        ap.error(f"--steady-from {args.steady_from}: must be in [0, 1)")
    args.db = args.db or os.path.join(args.out, "runs.sqlite")
    try:
        params = parse_params(args)
        vcs = [float(v) for v in args.vc.split(",")] if args.vc else None
        tests = select(load_dataset(args.data, tuple(args.status.split(","))), args.hmin, args.hmax, vcs)
        conds = conditions(tests)
        if args.limit:
            conds = conds[:args.limit]
        if not conds:
            raise InputError(f"dataset {args.data}: no test with status {args.status} and h in "
                             f"[{args.hmin}, {args.hmax}] mm" + (f" at vc {args.vc}" if vcs else ""))
    except InputError as e:
        print(f"validate: {e}", file=sys.stderr)
        return 2
    runs = plan_runs(conds, args, params)
    title = args.title or f"sphcut against {os.path.basename(args.data)}: set {args.set}" + \
        "".join(f", {kv}" for kv in args.param or [])
    if args.command == "plan":
        tot = 0.0
        print(f"{'vc':>6s} {'h mm':>6s} {'rn um':>6s} {'tests':>5s} {'ny':>4s} {'dx um':>6s} {'cut mm':>6s} "
              f"{'f':>6s} {'particles':>9s} {'steps':>8s}")
        for r in runs:
            i = r["inputs"]
            n, st = estimate(i)
            tot += n * st
            print(f"{i['vc']:6g} {i['h'] * 1e3:6.3f} {i['rn'] * 1e6:6.1f} {r['cond']['n']:5d} {i['ny']:4d} "
                  f"{1e6 * i['H'] / (i['ny'] - 1):6.2f} {i['cut'] * 1e3:6.3f} {i['massscale']:6.1f} {n:9.0f} {st:8.0f}")
        print(f"{len(runs)} runs, about {tot:.2e} particle-steps")
        return 0
    db = DB(args.db)
    if args.command == "run":
        rc = run_campaign(args, runs, db)
        write_report(args, runs, db, title)
        return rc
    write_report(args, runs, db, title)
    return 0


if __name__ == "__main__":
    sys.exit(main())
