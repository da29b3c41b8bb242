#!/usr/bin/env python3
"""sphcut's calibration tool: the material and friction inputs of the 2D cut
(examples/cutting-2d-ti6al4v/in.cutting) that best reproduce a dataset of orthogonal cutting tests.

    calibrate.py --fit jcA=700e6:1000e6 --fit mu=0.2:0.8 [--set seed003] [--weights Fc=1,Ft=1,hchip=0.5]
                 [--holdout 0.25] [--budget 200] [--jobs 4] [--lmp "$LMP"] [validate.py's options]

It is validate.py's runner driven by an optimiser: the dataset, its conditions, the geometry of a
condition's cut, the runs (several at once, --jobs) and the SQLite database of finished runs are
validate.py's (imported, not copied), so a calibration interrupted resumes without rerunning what is
stored, a second calibration (or a validate.py campaign) reuses every run whose inputs match, and
`sqlite3 OUT/runs.sqlite 'select inputs, results from runs'` shows what was run.  Candidate values
are rounded to 4 significant digits, so that proposals close to a stored one hit the database.

Objective: the weighted mean over the fit conditions and the targets (Fc, Ft, hchip) of the squared
relative error (simulated / measured - 1)^2.  Its noise comes from the runs' standard errors (5 block
means of the steady part) and, for the uncertainty, also from the measured scatter: with
r = sim / meas - 1 and var(r) = v, var(r^2) = 4 r^2 v + 2 v^2.  Two sets whose objectives differ by
less than that noise are reported as indistinguishable.

Optimiser (SciPy, which Debian ships as python3-scipy; maintained, no further dependency):
- --method lsq (the default): scipy.optimize.least_squares (trust-region reflective, bounds) on the
  vector of per-condition relative errors whose squares add up to J.  The forces are smooth, nearly
  linear functions of the material and friction inputs over a calibration's box, which a
  least-squares method exploits: a Jacobian from forward differences at the start (--step of the box,
  large against the forces' noise; the d candidates run as one batch), then Broyden's rank-one
  update from each evaluation, so an iteration costs one candidate (the conditions at once).
  Measured on the tests' tiny case: 6 evaluations against Nelder-Mead's 10 for one parameter.
  --init N starts it from the best point of a Latin-hypercube design (a rough objective, a start
  far from the optimum; the tests' coarse case needs it).
- --method nelder-mead: scipy.optimize.minimize's Nelder-Mead on J, parameters normalised to the box
  [0, 1]^d, from the best point of a Latin-hypercube design (scipy.stats.qmc, the start its first
  point).  No derivative, tolerant of noise at the scale of its simplex; a handful of evaluations a
  parameter more than lsq.
A Bayesian optimiser would need another dependency for a gain at 1-3 parameters that was not measured.

Uncertainty: the range of each parameter whose objective is within its noise (simulation and
measured scatter) of the best: a quadratic fitted to the objective at the evaluated points nearest the
best (how far the parameter moves, the others following, (H^-1)_ii, before the objective rises by its
noise), widened to every evaluated set within that noise of the best (a valley or a second basin the
quadratic does not see: two correlated parameters such as mu and jcA).  Sets inside cannot be told
from the best with these runs and measurements; it is not a confidence interval of the model's error.

Output (OUT, default calibration-out): calibration.json (fitted values, uncertainty, objective and
noise before and after, every evaluation), fitted.args (`--set ... --param NAME=VALUE ...` for
validate.py), fitted.var (`-var NAME VALUE` lines for in.cutting), fitted.lmp (the same as index
variables with the provenance as comments, for in.cutting's -var params), table.md and table.csv (simulated
against measured before and after on the fit and held-out conditions) and validate.py's reports
(table, plots) of the start set in OUT/before and of the fitted set in OUT/after.  doc/calibration.md is the user's guide.
"""
import argparse
import copy
import json
import math
import os
import random
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import validate  # noqa: E402
from validate import InputError  # noqa: E402

TARGETS = ("Fc", "Ft", "hchip")
FAILED_J = 1e3          # objective of a set whose runs failed (the optimiser moves away from it)


class BudgetSpent(Exception):
    pass


class DeadlineReached(Exception):
    pass


def run_until_deadline(args, runs, db, t_end):
    """validate.run_campaign within the --deadline; DeadlineReached where a run is left (killed at
    the deadline, not stored: the same command later runs it)"""
    def stored(r):
        return (db.get(r["key"]) or {}).get("status") in ("done", "failed")
    if all(stored(r) for r in runs):
        return
    if t_end:
        args.deadline = t_end - time.time()
        if args.deadline < args.min_left:
            raise DeadlineReached()
    validate.run_campaign(args, runs, db)
    if not all(stored(r) for r in runs):
        raise DeadlineReached()


def sig(x, digits=4):
    return float(f"{x:.{digits}g}")


# ---------------------------------------------------------------- command line
def parse_fit(items, start):
    """--fit NAME=LO:HI -> [(name, lo, hi)], checked against the start set"""
    if not items:
        raise InputError("--fit: give at least one NAME=LO:HI (e.g. --fit mu=0.2:0.8)")
    out = []
    for kv in items:
        if "=" not in kv or ":" not in kv.split("=", 1)[1]:
            raise InputError(f"--fit {kv}: expected NAME=LO:HI")
        k, rng = kv.split("=", 1)
        if k not in validate.KNOWN_PARAMS:
            raise InputError(f"--fit {k}: unknown parameter (known: {', '.join(sorted(validate.KNOWN_PARAMS))})")
        if any(k == o[0] for o in out):
            raise InputError(f"--fit {k}: given twice")
        try:
            lo, hi = (float(x) for x in rng.split(":", 1))
        except ValueError:
            raise InputError(f"--fit {kv}: the bounds are not numbers") from None
        if not (math.isfinite(lo) and math.isfinite(hi)):
            raise InputError(f"--fit {kv}: the bounds are not finite")
        if lo >= hi:
            raise InputError(f"--fit {kv}: lower bound {lo:g} >= upper bound {hi:g}")
        if k not in start:
            raise InputError(f"--fit {k}: the start set has no value for it: give one with --param {k}=VALUE")
        if not lo <= start[k] <= hi:
            raise InputError(f"--fit {kv}: the start {k} = {start[k]:g} is outside the bounds "
                             "(change the bounds or the start with --param)")
        out.append((k, lo, hi))
    return out


def parse_weights(text):
    w = {}
    for kv in text.split(","):
        k, w[k] = validate.name_value(kv, "--weights", TARGETS, "TARGET=WEIGHT", "target")
        if not (math.isfinite(w[k]) and w[k] >= 0):
            raise InputError(f"--weights {kv}: must be a finite number >= 0")
    if not any(v > 0 for v in w.values()):
        raise InputError(f"--weights {text}: no positive weight")
    return w


def split_holdout(conds, spec, seed):
    """(fit conditions, held-out conditions): --holdout K (an integer >= 1) or a fraction in (0, 1)"""
    try:
        x = float(spec)
    except ValueError:
        raise InputError(f"--holdout {spec}: not a number") from None
    if x == 0:
        return conds, []
    if 0 < x < 1:
        k = max(1, int(round(x * len(conds))))
    elif x >= 1 and x == int(x):
        k = int(x)
    else:
        raise InputError(f"--holdout {spec}: a number of conditions >= 1 or a fraction in (0, 1)")
    if k >= len(conds):
        raise InputError(f"--holdout {spec}: holds out {k} of {len(conds)} conditions, none left to fit")
    held = set(random.Random(seed).sample(range(len(conds)), k))
    return [c for i, c in enumerate(conds) if i not in held], [c for i, c in enumerate(conds) if i in held]


# ---------------------------------------------------------------- objective
def objective(runs, db, weights):
    """J, its noise from the runs' standard errors, its noise with the measured scatter too, the
    number of terms; None where a run is missing or failed"""
    tot = wsum = var_sim = var_all = 0.0
    n = se_unknown = 0
    terms = []
    for r in runs:
        got = db.get(r["key"])
        if not got or got["status"] != "done":
            return None
        res, c = got["results"], r["cond"]
        for q, w in weights.items():
            meas, sim = c.get(q), res.get(q)
            if w == 0 or not meas or sim is None:
                continue
            e = sim / meas - 1.0
            terms.append((f"{c['vc']:g}/{c['h']:g}/{q}", w, e))
            # a steady mean of one block (a chip thickness from one frame) has no standard error
            # (NaN): its term adds no simulation noise, counted in se_unknown
            se = res.get("se_" + q)
            if se is None or not math.isfinite(se):
                se, se_unknown = 0.0, se_unknown + 1
            vs = (se / meas) ** 2
            vm = (sim * (c.get("s" + q) or 0.0) / meas ** 2) ** 2
            tot += w * e * e
            wsum += w
            var_sim += w * w * (4 * e * e * vs + 2 * vs * vs)
            var_all += w * w * (4 * e * e * (vs + vm) + 2 * (vs + vm) ** 2)
            n += 1
    if wsum == 0:
        return None
    # the residuals whose squares add up to J (the least-squares method's vector)
    return {"J": tot / wsum, "noise_sim": math.sqrt(var_sim) / wsum, "noise": math.sqrt(var_all) / wsum,
            "terms": n, "se_unknown": se_unknown, "resid": {k: math.sqrt(w / wsum) * e for k, w, e in terms}}


class Calibration:
    def __init__(self, args, start, fit, fit_conds, db, weights):
        self.args, self.start, self.fit, self.conds, self.db, self.w = args, start, fit, fit_conds, db, weights
        self.cache = {}             # rounded parameter tuple -> evaluation
        self.evals = []
        self.sims_run = self.sims_reused = 0
        self.sims_used = 0          # budget: conditions x distinct candidates (stored ones too)
        self.t0 = time.time()
        self.t_end = self.t0 + args.deadline_s if args.deadline_s else 0
        self.wall_run = 0.0

    def params(self, x):
        p = dict(self.start)
        for xi, (k, lo, hi) in zip(x, self.fit):
            p[k] = sig(lo + min(1.0, max(0.0, xi)) * (hi - lo))
        return p

    def norm(self, p):
        return [(p[k] - lo) / (hi - lo) for k, lo, hi in self.fit]

    def tkey(self, p):
        return tuple(p[k] for k, _, _ in self.fit)

    def batch(self, xs):
        """evaluate candidates (normalised) as one batch of runs; the evaluations in order"""
        ps = [self.params(x) for x in xs]
        new = []
        for p in ps:
            if self.tkey(p) not in self.cache and self.tkey(p) not in [self.tkey(q) for q in new]:
                new.append(p)
        if new:
            if self.sims_used + len(new) * len(self.conds) > self.args.budget:
                # as many as the budget allows, in order
                room = (self.args.budget - self.sims_used) // len(self.conds)
                new = new[:room]
                if not new:
                    raise BudgetSpent()
            runs = {}
            per = []
            for p in new:
                rr = validate.plan_runs(self.conds, self.args, p)
                per.append(rr)
                for r in rr:
                    runs[r["key"]] = r
            stored = sum(1 for k in runs if (self.db.get(k) or {}).get("status") in ("done", "failed"))
            t = time.time()
            run_until_deadline(self.args, list(runs.values()), self.db, self.t_end)
            self.wall_run += time.time() - t
            self.sims_run += len(runs) - stored
            self.sims_reused += stored
            self.sims_used += len(new) * len(self.conds)
            for p, rr in zip(new, per):
                o = objective(rr, self.db, self.w)
                ev = {"params": {k: p[k] for k, _, _ in self.fit}, "x": self.norm(p),
                      "J": o["J"] if o else FAILED_J, "noise_sim": o["noise_sim"] if o else None,
                      "noise": o["noise"] if o else None, "failed": o is None,
                      "resid": o["resid"] if o else None, "se_unknown": o["se_unknown"] if o else 0}
                self.cache[self.tkey(p)] = ev
                self.evals.append(ev)
                self.progress(ev)
        out = []
        for p in ps:
            if self.tkey(p) not in self.cache:
                raise BudgetSpent()
            out.append(self.cache[self.tkey(p)])
        return out

    def best(self):
        ok = [e for e in self.evals if not e["failed"]]
        return min(ok, key=lambda e: e["J"]) if ok else None

    def progress(self, ev):
        b = self.best()
        left = self.args.budget - self.sims_used
        per_sim = self.wall_run / self.sims_run if self.sims_run else None
        eta = f"at most about {left * per_sim / self.args.jobs:.0f} s left" if per_sim else "time left unknown"
        vals = " ".join(f"{k} {v:g}" for k, v in ev["params"].items())
        j = "FAILED" if ev["failed"] else f"J {ev['J']:.4g} +- {ev['noise_sim']:.2g}"
        if ev.get("se_unknown"):
            j += f" ({ev['se_unknown']} terms without a standard error)"
        print(f"calibrate: evaluation {len(self.evals)}: {vals}: {j}; best J {b['J']:.4g} "
              f"({' '.join(f'{k} {v:g}' for k, v in b['params'].items())}); simulations {self.sims_run} run, "
              f"{self.sims_reused} reused, {self.sims_used}/{self.args.budget} of the budget; {eta}"
              if b else f"calibrate: evaluation {len(self.evals)}: {vals}: {j}", flush=True)

    def run(self):
        if self.args.method == "lsq":
            return self.run_lsq()
        from scipy.optimize import minimize
        from scipy.stats import qmc
        d = len(self.fit)
        x0 = self.norm(self.start)
        n = self.args.init if self.args.init is not None else 2 * d + 1
        design = [x0]
        if n > 1:
            design += [list(x) for x in qmc.LatinHypercube(d=d, seed=self.args.seed).random(n - 1)]
        try:
            self.batch(design)
            b = self.best()
            xb = b["x"] if b else x0
            # the initial simplex: the best point and a step of --step of the box along each axis,
            # inwards where the step would leave the box
            simplex = [xb]
            for i in range(d):
                y = list(xb)
                y[i] = y[i] + self.args.step if y[i] + self.args.step <= 1 else y[i] - self.args.step
                simplex.append(y)
            fatol = (b["noise_sim"] or 0.0) if b else 0.0
            minimize(lambda x: self.batch([list(x)])[0]["J"], xb, method="Nelder-Mead",
                     bounds=[(0.0, 1.0)] * d,
                     options={"initial_simplex": simplex, "xatol": self.args.xtol, "fatol": fatol,
                              "maxfev": 10 ** 6})
            self.stop = "converged (simplex smaller than --xtol and its objectives within the noise)"
        except BudgetSpent:
            self.stop = f"budget of {self.args.budget} simulations spent"
        return self.best()

    # ------------------------------------------------------------ least squares
    def rvec(self, ev):
        """the evaluation's residual vector in the order of the start's terms (a term missing in a
        run, a chip thickness that could not be measured, takes the start's value: no pull either way)"""
        import numpy as np
        if ev["failed"]:
            return np.full(len(self.rkeys), math.sqrt(FAILED_J / len(self.rkeys)))
        return np.array([ev["resid"].get(k, self.r0.get(k, 0.0)) for k in self.rkeys])

    def fd_jacobian(self, x, ev):
        """forward differences of --step of the box along each axis (inwards at a bound), the d
        candidates as one batch; the steps are the evaluated ones (after rounding)"""
        import numpy as np
        d = len(self.fit)
        ys = []
        for i in range(d):
            y = list(x)
            y[i] = y[i] + self.args.step if y[i] + self.args.step <= 1 else y[i] - self.args.step
            ys.append(y)
        evs = self.batch(ys)
        J = np.zeros((len(self.rkeys), d))
        r = self.rvec(ev)
        for i, e in enumerate(evs):
            dx = e["x"][i] - ev["x"][i]
            J[:, i] = (self.rvec(e) - r) / dx
        return J

    def run_lsq(self):
        """scipy.optimize.least_squares (trust-region reflective, bounds [0, 1]^d) on the residual
        vector whose squares add up to J.  The Jacobian: forward differences at the start (d
        candidates as one batch), then Broyden's rank-one update from each evaluation the optimiser
        makes (--jacobian broyden, the default: one candidate an iteration), or forward differences
        at every accepted point (--jacobian fd: d + 1 candidates an iteration)"""
        import numpy as np
        from scipy.optimize import least_squares
        from scipy.stats import qmc
        d = len(self.fit)
        n = self.args.init if self.args.init is not None else 1
        design = [self.norm(self.start)]
        if n > 1:
            design += [list(x) for x in qmc.LatinHypercube(d=d, seed=self.args.seed).random(n - 1)]
        try:
            # the start, or the best of a design (--init N: a rough objective or a start far away)
            self.batch(design)
            ev0 = self.best()
            if ev0 is None:
                self.stop = "the start set's runs failed"
                return None
            x0 = ev0["x"]
            self.rkeys, self.r0 = sorted(ev0["resid"]), ev0["resid"]
            state = {"J": None, "base": ev0, "seen": len(self.evals)}
            self.jac_at = None

            def evaluate(x):
                return self.batch([list(x)])[0]

            def fun(x):
                return self.rvec(evaluate(x))

            def jac(x, f=None):
                ev = evaluate(x)
                if state["J"] is None or self.args.jacobian == "fd":
                    state["J"] = self.fd_jacobian(ev["x"], ev)
                else:
                    # Broyden: J += (dr - J s) s^T / s^T s for each evaluation since the last
                    # Jacobian, against the last accepted point; then the current one
                    J, b = state["J"], state["base"]
                    xb, rb = np.array(b["x"]), self.rvec(b)
                    for e in self.evals[state["seen"]:] + [ev]:
                        sx = np.array(e["x"]) - xb
                        if e is b or e["failed"] or float(sx @ sx) < 1e-12:
                            continue
                        J = J + np.outer(self.rvec(e) - rb - J @ sx, sx) / float(sx @ sx)
                    state["J"] = J
                state["base"], state["seen"] = ev, len(self.evals)
                self.jac_at = (ev, state["J"])
                return state["J"]

            # stop when an iteration lowers J by less than the start's noise (a smaller gain cannot be
            # told from the swing of the forces) or the step is below --xtol of the box
            ftol = max(1e-8, min(0.1, (ev0["noise_sim"] or 0.0) / max(ev0["J"], 1e-30)))
            sol = least_squares(fun, np.array(x0), jac=jac, bounds=(np.zeros(d), np.ones(d)), method="trf",
                                x_scale=np.ones(d), ftol=ftol, xtol=self.args.xtol, gtol=1e-10,
                                max_nfev=10 ** 4)
            self.stop = f"converged ({sol.message})"
        except BudgetSpent:
            self.stop = f"budget of {self.args.budget} simulations spent"
        return self.best()

    def uncertainty(self, best, dJ):
        """per parameter: (half-width, low, high) in its units and how it was found.  The interval
        covers the quadratic's (how far a parameter moves, the others following, before the objective
        rises by dJ) and every evaluated set within dJ of the best (those cannot be told from it: a
        valley or a second basin that the quadratic does not see); the half-width is the larger
        distance from the fitted value to the interval's ends"""
        import numpy as np
        d = len(self.fit)
        pts = [e for e in self.evals if not e["failed"]]
        nq = (d + 1) * (d + 2) // 2
        xb = np.array(best["x"])
        span = np.array([hi - lo for _, lo, hi in self.fit])
        quad = None
        gn = getattr(self, "jac_at", None)
        if gn is not None and dJ > 0:
            # the Gauss-Newton curvature of J = sum r^2 at the last Jacobian: J rises by
            # s^T (Jr^T Jr) s, so parameter i moves by sqrt(dJ (Jr^T Jr)^-1_ii), the others following
            A = gn[1].T @ gn[1]
            if np.linalg.matrix_rank(A) == d:
                quad = np.sqrt(dJ * np.diag(np.linalg.inv(A))) * span
        if quad is None and len(pts) >= nq + 1 and dJ > 0:
            near = sorted(pts, key=lambda e: float(np.sum((np.array(e["x"]) - xb) ** 2)))[:max(nq + 2, 3 * nq)]
            X = np.array([e["x"] for e in near]) - xb
            cols = [np.ones(len(X))] + [X[:, i] for i in range(d)] + \
                [X[:, i] * X[:, j] for i in range(d) for j in range(i, d)]
            coef = np.linalg.lstsq(np.array(cols).T, np.array([e["J"] for e in near]), rcond=None)[0]
            H = np.zeros((d, d))
            m = 1 + d
            for i in range(d):
                for j in range(i, d):
                    H[i, j] = H[j, i] = coef[m] * (2 if i == j else 1)
                    m += 1
            if np.all(np.linalg.eigvalsh(H) > 0):
                quad = np.sqrt(2 * dJ * np.diag(np.linalg.inv(H))) * span
        within = [e for e in pts if e["J"] <= best["J"] + dJ]
        out = {}
        for i, (k, _, _) in enumerate(self.fit):
            v = best["params"][k]
            lo = min(e["params"][k] for e in within)
            hi = max(e["params"][k] for e in within)
            if quad is not None:
                lo, hi = min(lo, v - quad[i]), max(hi, v + quad[i])
            out[k] = (max(v - lo, hi - v), lo, hi)
        how = ("the Gauss-Newton curvature of the residuals at the optimiser's last Jacobian, " if gn is not None
               and quad is not None else
               f"quadratic fit to the {min(len(pts), max(nq + 2, 3 * nq))} evaluated sets nearest the best, "
               if quad is not None else "the quadratic not resolved (too few sets or curvature not positive: "
               "a lower bound), ") + f"widened to the {len(within)} evaluated sets within the noise of the best"
        return out, how

# ---------------------------------------------------------------- report
def compare(args, conds, db, sets, weights):
    """rows of simulated against measured for each named parameter set"""
    rows = []
    for c in conds:
        row = {"vc": c["vc"], "h": c["h"], "rn_um": c["rn_um"], "holdout": c.get("holdout", False)}
        for q in TARGETS:
            row[q + "_meas"], row["s" + q + "_meas"] = c[q], c["s" + q]
        for name, p in sets.items():
            r = validate.plan_runs([c], args, p)[0]
            got = db.get(r["key"])
            res = got["results"] if got and got["status"] == "done" else {}
            for q in TARGETS:
                row[f"{q}_{name}"] = res.get(q)
                row[f"se{q}_{name}"] = res.get("se_" + q)
        rows.append(row)
    return rows


def fmt(x, spec=".1f"):
    return "-" if x is None else format(x, spec)


def err(sim, meas):
    return None if sim is None or not meas else 100 * (sim / meas - 1)


def fitted_input(args, fit, start, fitted, unc, ob, fit_conds, held, stop):
    """the fitted set as LAMMPS index variables, for in.cutting's -var params FILE: index variables
    defined first keep their value (in.cutting's own defaults and a later -var do not change them;
    a -var on the command line still wins), and comment lines saying where the set comes from"""
    def conds(cs):
        return ", ".join(f"{c['vc']:g}/{c['h']:g}" for c in cs) or "none"

    def obj(name, part):
        o = ob[name][part]
        return f"{o['J']:.4g} +- {o['noise_sim']:.2g}" if o else "-"
    lines = [f"# {', '.join(k for k, _, _ in fit)} fitted by bench/validation/calibrate.py (sphcut) to "
             f"{os.path.basename(args.data)}",
             f"# start set {args.set}" + "".join(f", {kv}" for kv in args.param or []) + f"; weights {args.weights}"
             + ("" if args.chip else " (no chip)") + f"; {stop}",
             f"# fitted on {len(fit_conds)} conditions (vc m/min / h mm): {conds(fit_conds)}",
             f"# held out {len(held)}: {conds(held)}",
             f"# objective (mean squared relative error) start -> fitted: fit {obj('start', 'fit')} -> "
             f"{obj('fitted', 'fit')}; held out {obj('start', 'holdout')} -> {obj('fitted', 'holdout')}"]
    for k, lo, hi in fit:
        lines.append(f"# {k}: {fitted[k]:g} +- {unc[k][0]:.2g} (bounds {lo:g} - {hi:g}; start {start[k]:g}; "
                     f"objective within its noise over {unc[k][1]:.4g} - {unc[k][2]:.4g})")
    lines += [f"# the runs' resolution (validate.py): {args.per_h:g} spacings per h, {args.per_rn:g} per edge radius, "
              f"cut {args.cut_h:g} h or {args.cut_rn:g} rn, steady from {args.steady_from:g} of the cut, thermal "
              f"{args.thermal}; the set is fitted at that resolution",
              "# command: python3 bench/validation/calibrate.py " + " ".join(sys.argv[1:])]
    lines += [f"variable     {k:<9} index {fitted[k]!r}" for k in sorted(fitted)]
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--fit", action="append", help="NAME=LO:HI: fit this input of in.cutting within the bounds "
                    "(repeat; any of validate.py's --param names)")
    ap.add_argument("--weights", default="Fc=1,Ft=1,hchip=0.5", help="TARGET=W,...: targets Fc, Ft, hchip "
                    "and their weights (default Fc=1,Ft=1,hchip=0.5)")
    ap.add_argument("--holdout", default="0", help="K conditions (integer) or a fraction held out of the fit; "
                    "their error is reported before and after (default 0)")
    ap.add_argument("--budget", type=int, default=200, help="at most this many simulations (conditions x "
                    "candidates, stored ones counted too; default 200)")
    ap.add_argument("--maxiter", type=int, help="at most this many evaluations (sets --budget to MAXITER x conditions "
                    "if smaller)")
    ap.add_argument("--method", default="lsq", choices=("lsq", "nelder-mead"),
                    help="lsq: least squares on the per-condition errors (SciPy least_squares), the default; "
                    "nelder-mead: a derivative-free simplex on J after a Latin-hypercube design")
    ap.add_argument("--jacobian", default="broyden", choices=("broyden", "fd"),
                    help="lsq's Jacobian: forward differences at the start, then Broyden updates (one "
                    "candidate an iteration; default), or forward differences at every accepted point")
    ap.add_argument("--init", type=int, help="points of the initial design, the start included (default: "
                    "nelder-mead 2 d + 1, lsq 1: the start only)")
    ap.add_argument("--step", type=float, default=0.15, help="initial simplex step (nelder-mead) or the "
                    "finite-difference step (lsq), a fraction of the box (0.15)")
    ap.add_argument("--xtol", type=float, default=0.01, help="stop when the simplex is this small (box fraction)")
    ap.add_argument("--deadline", dest="deadline_s", type=float, default=0,
                    help="stop this many seconds after the start (runs not finished are not stored; the "
                    "same command again resumes), exit 3; default: none")
    ap.add_argument("--seed", type=int, default=1, help="seed of the design and of the hold-out choice")
    ap.add_argument("--out", default="calibration-out", help="output folder (default calibration-out)")
    # validate.py's options (the same names and defaults)
    ap.add_argument("--data", default=validate.DATASET, help="dataset CSV (validate.py's format)")
    ap.add_argument("--db", help="SQLite database of the runs (default OUT/runs.sqlite; validate.py's works)")
    ap.add_argument("--status", default="ok,short")
    ap.add_argument("--hmin", type=float, default=0.02)
    ap.add_argument("--hmax", type=float, default=0.2)
    ap.add_argument("--vc", help="only these speeds [m/min], comma-separated")
    ap.add_argument("--limit", type=int, default=0, help="only the first N conditions")
    ap.add_argument("--set", default="seed003", help="start set: " + ", ".join(validate.PARAM_SETS))
    ap.add_argument("--param", action="append", help="NAME=VALUE: change one input of the start set")
    ap.add_argument("--per-h", type=float, default=10.0)
    ap.add_argument("--per-rn", type=float, default=4.0)
    ap.add_argument("--cut-h", type=float, default=5.0)
    ap.add_argument("--cut-rn", type=float, default=5.0)
    ap.add_argument("--steady-from", type=float, default=0.4)
    ap.add_argument("--vref", type=float, default=318.5)
    ap.add_argument("--thermal", type=int, default=1, choices=(0, 1))
    ap.add_argument("--no-chip", dest="chip", action="store_false", help="no dump, no chip thickness")
    ap.add_argument("--keep-dumps", action="store_true")
    ap.add_argument("--lmp", help="LAMMPS command (default $LMP)")
    ap.add_argument("--jobs", type=int, default=1, help="runs at a time (default 1)")
    ap.add_argument("--retry-failed", action="store_true")
    ap.add_argument("--rerun-stale", action="store_true")
    args = ap.parse_args(argv)
    args.deadline, args.min_left = 0, 60
    args.db = args.db or os.path.join(args.out, "runs.sqlite")
    try:
        for name in ("jobs", "budget"):
            if getattr(args, name) < 1:
                raise InputError(f"--{name} {getattr(args, name)}: must be >= 1")
        for name in ("per_h", "per_rn", "cut_h"):
            if not getattr(args, name) > 0:
                raise InputError(f"--{name.replace('_', '-')} {getattr(args, name)}: must be > 0")
        if not 0 <= args.steady_from < 1:
            raise InputError(f"--steady-from {args.steady_from}: must be in [0, 1)")
        if not 0 < args.step <= 0.5:
            raise InputError(f"--step {args.step}: must be in (0, 0.5]")
        start = validate.parse_params(args)
        fit = parse_fit(args.fit, start)
        weights = parse_weights(args.weights)
        if not args.chip:
            weights["hchip"] = 0.0
        vcs = [float(v) for v in args.vc.split(",")] if args.vc else None
        conds = validate.conditions(validate.select(validate.load_dataset(args.data, tuple(args.status.split(","))),
                                                    args.hmin, args.hmax, vcs))
        if args.limit:
            conds = conds[:args.limit]
        if not conds:
            raise InputError(f"dataset {args.data}: no test with status {args.status} and h in "
                             f"[{args.hmin}, {args.hmax}] mm" + (f" at vc {args.vc}" if vcs else ""))
        fit_conds, held = split_holdout(conds, args.holdout, args.seed)
        if args.maxiter is not None:
            if args.maxiter < 1:
                raise InputError(f"--maxiter {args.maxiter}: must be >= 1")
            args.budget = min(args.budget, args.maxiter * len(fit_conds))
        if args.budget < len(fit_conds):
            raise InputError(f"--budget {args.budget}: less than one evaluation ({len(fit_conds)} conditions)")
        for c in held:
            c["holdout"] = True
        if not any(c.get(q) for c in fit_conds for q, w in weights.items() if w > 0):
            raise InputError("--weights: no fit condition has a measurement of a weighted target")
    except InputError as e:
        print(f"calibrate: {e}", file=sys.stderr)
        return 2

    db = validate.DB(args.db)
    print(f"calibrate: {len(fit_conds)} fit conditions, {len(held)} held out; fitting "
          + ", ".join(f"{k} in [{lo:g}, {hi:g}] from {start[k]:g}" for k, lo, hi in fit)
          + f"; budget {args.budget} simulations, {args.jobs} at a time; runs in {args.db}", flush=True)
    cal = Calibration(args, start, fit, fit_conds, db, weights)
    try:
        best = cal.run()
        if best is not None:
            # the start and the fitted set on every condition (the held-out ones run now)
            fitted = dict(start, **best["params"])
            allruns = {}
            for p in (start, fitted):
                for r in validate.plan_runs(conds, args, p):
                    allruns[r["key"]] = r
            run_until_deadline(args, list(allruns.values()), db, cal.t_end)
    except DeadlineReached:
        b = cal.best()
        if b:
            # the best set so far for validate.py (best.args), e.g. its held-out conditions in another call
            os.makedirs(args.out, exist_ok=True)
            with open(os.path.join(args.out, "best.args"), "w") as f:
                f.write(f"--set {args.set} " + " ".join(f"--param {k}={v!r}" for k, v in
                                                        sorted(dict(start, **b["params"]).items())) + "\n")
        print(f"calibrate: deadline reached after {time.time() - cal.t0:.0f} s, {len(cal.evals)} evaluations, "
              f"{cal.sims_run} simulations run, {cal.sims_used} of the budget used"
              + (f", best J {b['J']:.4g} ({b['params']}; OUT/best.args)" if b else "")
              + "; the same command resumes (stored runs are reused; --budget "
              f"{cal.sims_used} reports what is stored)", flush=True)
        return 3
    if best is None:
        print("calibrate: every evaluation failed (see the runs' logs under OUT/runs)", file=sys.stderr)
        return 1
    ob = {name: {part: objective(validate.plan_runs(cs, args, p), db, weights) if cs else None
                 for part, cs in (("fit", fit_conds), ("holdout", held))}
          for name, p in (("start", start), ("fitted", fitted))}
    b0 = cal.cache.get(cal.tkey(start))
    dJ = best["noise"] or 0.0
    unc, how = cal.uncertainty(best, dJ)

    lines = [f"# Calibration of {', '.join(k for k, _, _ in fit)} against {os.path.basename(args.data)}", "",
             f"Start set {args.set}" + "".join(f", {kv}" for kv in args.param or []) +
             f"; weights {args.weights if args.chip else args.weights + ' (no chip: hchip 0)'}; "
             f"{len(fit_conds)} fit conditions, {len(held)} held out; {len(cal.evals)} evaluations, "
             f"{cal.sims_run} simulations run, {cal.sims_reused} reused; {cal.stop}.", "",
             "| parameter | bounds | start | fitted | +- | indistinguishable range |", "|---|---|---|---|---|---|"]
    for k, lo, hi in fit:
        lines.append(f"| {k} | {lo:g} - {hi:g} | {start[k]:g} | {fitted[k]:g} | {unc[k][0]:.2g} "
                     f"| {unc[k][1]:.4g} - {unc[k][2]:.4g} |")
    lines += ["", f"Uncertainty: the parameter range whose objective is within its noise {dJ:.2g} (runs' standard "
              f"errors and measured scatter) of the best: {how}.", "",
              "| objective (mean squared relative error) | start | fitted |", "|---|---|---|"]
    for part in ("fit", "holdout"):
        if ob["start"][part]:
            s, f = ob["start"][part], ob["fitted"][part]
            lines.append(f"| {part} conditions | {fmt(s and s['J'], '.4g')} +- {fmt(s and s['noise_sim'], '.2g')} "
                         f"| {fmt(f and f['J'], '.4g')} +- {fmt(f and f['noise_sim'], '.2g')} |")
    for part in ("fit", "holdout"):
        s, f = ob["start"][part], ob["fitted"][part]
        if s and f:
            noise = math.hypot(s["noise_sim"], f["noise_sim"])
            same = abs(s["J"] - f["J"]) < noise
            lines.append(f"- {part} conditions: the fitted set's objective differs from the start's by "
                         f"{f['J'] - s['J']:+.3g}, " + ("LESS than the simulation noise " if same else "more than the "
                                                         "simulation noise ") + f"{noise:.2g}")
    close = [e for e in cal.evals if e is not best and not e["failed"] and best["noise_sim"] is not None
             and e["noise_sim"] is not None and e["J"] - best["J"] < math.hypot(e["noise_sim"], best["noise_sim"])]
    lines.append(f"- {len(close)} other evaluated sets are within the simulation noise of the best")
    lines += ["", "Simulated (start -> fitted) against measured; errors simulated / measured - 1; "
              "H: held out of the fit.", "",
              "| vc | h mm | rn um | | Fc meas. | Fc start | Fc fitted | Ft meas. | Ft start | Ft fitted "
              "| hchip meas. | hchip start | hchip fitted |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    rows = compare(args, conds, db, {"start": start, "fitted": fitted}, weights)
    for r in rows:
        cells = [f"{r['vc']:g}", f"{r['h']:g}", f"{r['rn_um']:.1f}", "H" if r["holdout"] else ""]
        for q in TARGETS:
            cells.append(f"{fmt(r[q + '_meas'])}")
            for name in ("start", "fitted"):
                cells.append(f"{fmt(r[f'{q}_{name}'])} ({fmt(err(r[f'{q}_{name}'], r[q + '_meas']), '+.0f')} %)")
        lines.append("| " + " | ".join(cells) + " |")
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "table.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    if rows:
        cols = list(rows[0])
        with open(os.path.join(args.out, "table.csv"), "w") as f:
            f.write(",".join(cols) + "\n")
            for r in rows:
                f.write(",".join("" if r[c] is None else str(r[c]) for c in cols) + "\n")
    with open(os.path.join(args.out, "fitted.args"), "w") as f:
        f.write(f"--set {args.set} " + " ".join(f"--param {k}={fitted[k]!r}" for k in sorted(fitted)) + "\n")
    with open(os.path.join(args.out, "fitted.var"), "w") as f:
        f.write("".join(f"-var {k} {fitted[k]!r}\n" for k in sorted(fitted)))
    # the set as a LAMMPS input for in.cutting (-var params FILE), with where it comes from
    with open(os.path.join(args.out, "fitted.lmp"), "w") as f:
        f.write(fitted_input(args, fit, start, fitted, unc, ob, fit_conds, held, cal.stop))
    with open(os.path.join(args.out, "calibration.json"), "w") as f:
        json.dump({"data": args.data, "set": args.set, "param": args.param, "weights": weights,
                   "fit": [{"name": k, "lo": lo, "hi": hi, "start": start[k], "value": fitted[k],
                            "uncertainty": unc[k][0], "range": [unc[k][1], unc[k][2]]} for k, lo, hi in fit],
                   "uncertainty_method": how, "objective_noise": dJ, "objective": ob,
                   "start_evaluation": b0, "fitted": fitted, "stop": cal.stop,
                   "fit_conditions": [[c["vc"], c["h"]] for c in fit_conds],
                   "holdout_conditions": [[c["vc"], c["h"]] for c in held],
                   "simulations_run": cal.sims_run, "simulations_reused": cal.sims_reused,
                   "evaluations": cal.evals}, f, indent=1)
    print("\n".join(lines))
    # validate.py's tables and plots of the start (OUT/before) and the fitted set (OUT/after)
    for sub, p in (("before", start), ("after", fitted)):
        rep = copy.copy(args)
        rep.out = os.path.join(args.out, sub)
        try:
            import contextlib
            import io
            with contextlib.redirect_stdout(io.StringIO()):
                validate.write_report(rep, validate.plan_runs(conds, args, p), db,
                                      f"{'start' if sub == 'before' else 'fitted'} set "
                                      f"({', '.join(f'{k} {p[k]:g}' for k, _, _ in fit)})")
        except Exception as e:      # the calibration stands; the report of validate.py is extra
            print(f"calibrate: no report in {rep.out}: {type(e).__name__}: {e}")
    print(f"calibrate: {os.path.join(args.out, 'fitted.args')} (for validate.py), fitted.var (-var lines for "
          f"in.cutting), fitted.lmp (-var params FILE of in.cutting), calibration.json, table.md", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
