#!/usr/bin/python3
"""The fit behind `suturesim calibrate` (issue 28, docs/calibration.md).

Usage: /usr/bin/python3 postprocess/calibrate.py FOLDER/calibration_plan.json
(written by `suturesim calibrate`, which checks the calibration file first).

The objective is F(p) = sum_m w_m e_m(p)^2 over the calibration's weighted error
columns e_m of the study layer (study/case_metrics.h), one case at parameters p against
the study's reference. SciPy's least_squares (method "trf": a trust-region reflective
Gauss-Newton method that keeps p within its bounds; Branch, Coleman & Li 1999) minimises
it through residuals r whose squares sum to F:
- probe.<p>: its three components sqrt(w) (u - u_ref)/|u_ref|, whose norm is the study's
  |u - u_ref|/|u_ref| (checked on every run against study.json, to 1e-9);
- a scalar: sqrt(w) times the study's signed relative error;
- any other column (curve L2, surface L2): sqrt(w) times the study's value.
A parameter with lower bound > 0 is fitted in z = ln p, otherwise in z = (p - lower) /
(upper - lower). The Jacobian is a forward difference in z of step h (Calibration/
Difference step), its n runs one batch of cases, so --jobs N runs them N at a time.

Every batch of parameter vectors is a `suturesim study <calibration.prm> --case-list`
run into FOLDER/runs: the study layer runs the cases (no shell, one process per case),
reuses any case of the same parameters (the reference is run once) and measures them.

Standard errors: cov(p) = s^2 (J^T J)^-1 with J = dr/dp at the fit and s^2 = 2 cost /
(m - n) the residual variance (m residuals, n parameters; the usual nonlinear
least-squares estimate, e.g. Seber & Wild 1989, sec. 2.1). With an exact fit (a
synthetic reference) s^2 ~ 0 and so are they: the residual then carries no noise.

Writes FOLDER/calibration.json, FOLDER/calibrated.prm (a scene fragment of the fitted
values), FOLDER/calibration_history.{png,pdf} (the objective) and
FOLDER/calibration_errors.{png,pdf} (train and validation errors, initial and fitted). Exit 0 converged, 3 stopped at
Max evaluations (the best point found is written), 2 a run the study rejected.
"""
import hashlib
import json
import math
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import scipy
from scipy.optimize import least_squares

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


class StudyFailed(Exception):
    """A batch the study command rejected (its exit code and error line)."""

    def __init__(self, code, line):
        super().__init__(line)
        self.code = code


class Fit:
    def __init__(self, plan):
        self.plan = plan
        self.folder = Path(plan["folder"])
        self.runs = self.folder / "runs"
        self.batches = self.folder / "batches"
        self.batches.mkdir(parents=True, exist_ok=True)
        self.parameters = plan["parameters"]
        self.logarithmic = [q["lower"] > 0 for q in self.parameters]
        self.weights = [(w["column"], w["weight"]) for w in plan["weights"]]
        self.cache = {}  # case name -> evaluation
        self.history = []  # the objective's runs (not the Jacobian's), in order
        self.batch_count = 0
        self.labels = None
        self.reference = None  # the reference run's metrics, read once (it is run once)

    # --- parameters <-> optimisation variables ---------------------------------------
    def to_z(self, p):
        return np.array([math.log(v) if log else (v - q["lower"]) / (q["upper"] - q["lower"])
                         for v, q, log in zip(p, self.parameters, self.logarithmic)])

    def to_p(self, z):
        return [math.exp(v) if log else q["lower"] + v * (q["upper"] - q["lower"])
                for v, q, log in zip(z, self.parameters, self.logarithmic)]

    def z_bounds(self):
        lower = [math.log(q["lower"]) if log else 0.0 for q, log in zip(self.parameters, self.logarithmic)]
        upper = [math.log(q["upper"]) if log else 1.0 for q, log in zip(self.parameters, self.logarithmic)]
        return np.array(lower), np.array(upper)

    def settings(self, p):
        return ["%s=%s" % (q["path"], repr(float(v))) for q, v in zip(self.parameters, p)]

    # --- running cases through the study layer ---------------------------------------
    @staticmethod
    def case_name(prefix, settings):
        return prefix + hashlib.sha1("\n".join(settings).encode()).hexdigest()[:12]

    def run(self, cases):
        """Runs [(name, settings)] as one study batch; returns study.json's rows by name."""
        self.batch_count += 1
        listing = self.batches / ("batch_%04d.txt" % self.batch_count)
        text = ";\n".join(name + ": " + ", ".join('"%s"' % s for s in settings) for name, settings in cases)
        listing.write_text(text + "\n")
        command = [self.plan["executable"], "study", self.plan["calibration"], "--output", str(self.runs),
                   "--jobs", str(self.plan["jobs"]), "--case-list", str(listing), "--no-figures"]
        for s in self.plan["overrides"]:
            command += ["--set", s]
        log = listing.with_suffix(".log")
        with open(log, "w") as out:
            code = subprocess.call(command, stdout=out, stderr=subprocess.STDOUT)
        if code != 0:
            lines = [l for l in log.read_text().splitlines() if l.startswith("error:")]
            raise StudyFailed(code, lines[-1] if lines else "the study exited with %d (%s)" % (code, log))
        rows = json.loads((self.runs / "study.json").read_text())["cases"]
        return {r["name"]: r for r in rows}

    def metrics_of(self, name):
        summary = json.loads((self.runs / "cases" / name / "summary.json").read_text())
        return summary["metrics"]

    def residuals(self, name, row):
        """The weighted residual vector of one completed case, with its labels."""
        if self.reference is None:
            self.reference = self.metrics_of("reference")
        ref = self.reference
        own = self.metrics_of(name)
        r, labels = [], []
        for column, w in self.weights:
            e = row["errors"].get(column)
            if e is None:
                raise RuntimeError("case %s has no error %s (status %s: %s)" %
                                   (name, column, row["status"], row["reason"]))
            if column.startswith("probe."):
                probe = column[len("probe."):]
                u = np.array([own["%s_displacement_%s" % (probe, c)] for c in "xyz"])
                u_ref = np.array([ref["%s_displacement_%s" % (probe, c)] for c in "xyz"])
                comp = (u - u_ref) / np.linalg.norm(u_ref)
                if abs(np.linalg.norm(comp) - e) > 1e-9 * max(1.0, e):
                    raise RuntimeError("probe %s: %.17g here, %.17g in study.json" % (probe, np.linalg.norm(comp), e))
                r += list(math.sqrt(w) * comp)
                labels += ["%s.%s" % (column, c) for c in "xyz"]
            else:
                r.append(math.sqrt(w) * e)
                labels.append(column)
        self.labels = labels
        return np.array(r)

    def evaluate(self, points, counted):
        """Residuals at each parameter vector of @p points (one batch); the counted ones
        (the objective's own runs) go into the history."""
        cases, names = [], []
        for p in points:
            s = self.settings(p)
            name = self.case_name("p", s)
            names.append(name)
            if name not in self.cache and all(n != name for n, _ in cases):
                cases.append((name, s))
        if cases:
            rows = self.run(cases)
            for name, _ in cases:
                row = rows[name]
                if row["status"] != "completed":
                    raise StudyFailed(3, "error: calibrate: the run at %s %s: %s" %
                                      (", ".join(dict(cases)[name]), row["status"], row["reason"]))
                r = self.residuals(name, row)
                self.cache[name] = {"r": r, "errors": row["errors"], "costs": row["costs"]}
        out = [self.cache[n]["r"] for n in names]
        for p, n, r in zip(points, names, out):
            if counted:
                self.history.append({"evaluation": len(self.history) + 1, "case": n,
                                     "values": [float(v) for v in p], "objective": float(r @ r)})
        return out

    # --- what least_squares calls ---------------------------------------------------
    def fun(self, z):
        return self.evaluate([self.to_p(z)], counted=True)[0]

    def jac(self, z):
        h = self.plan["difference_step"]
        lower, upper = self.z_bounds()
        steps, points = [], []
        for k in range(len(z)):
            dz = h if z[k] + h <= upper[k] else -h  # stay inside the bounds
            zk = np.array(z, dtype=float)
            zk[k] += dz
            steps.append(dz)
            points.append(self.to_p(zk))
        centre = self.fun_cached(z)
        shifted = self.evaluate(points, counted=False)
        return np.column_stack([(s - centre) / dz for s, dz in zip(shifted, steps)])

    def fun_cached(self, z):
        return self.evaluate([self.to_p(z)], counted=False)[0]


def standard_errors(fit, result):
    """cov(p) = s^2 (J_p^T J_p)^-1 at the fit, J_p = J_z dz/dp; None where undefined."""
    p = fit.to_p(result.x)
    dzdp = [1 / v if log else 1 / (q["upper"] - q["lower"]) for v, q, log in zip(p, fit.parameters, fit.logarithmic)]
    jp = result.jac * np.array(dzdp)
    m, n = jp.shape
    if m <= n:
        return [None] * n, jp
    s2 = 2 * result.cost / (m - n)
    cov = s2 * np.linalg.pinv(jp.T @ jp)
    return [float(math.sqrt(max(c, 0.0))) for c in np.diag(cov)], jp


def write_fragment(path, fit, p, command):
    """The fitted values as a scene file's nested subsections (one tree)."""
    tree = {}
    for q, v in zip(fit.parameters, p):
        *sections, key = q["path"].split("/")
        node = tree
        for s in sections:
            node = node.setdefault(s, {})
        node[key] = repr(float(v))
    lines = ["# Fitted by %s" % command,
             "# (calibration.json has the fit: standard errors, train and validation errors)"]

    def emit(node, depth):
        for key, value in node.items():
            if isinstance(value, dict):
                lines.append("  " * depth + "subsection " + key)
                emit(value, depth + 1)
                lines.append("  " * depth + "end")
            else:
                lines.append("  " * depth + "set %s = %s" % (key, value))

    emit(tree, 0)
    path.write_text("\n".join(lines) + "\n")


def draw_history(fit, folder):
    fig, ax = plt.subplots(figsize=(6, 4))
    f = [h["objective"] for h in fit.history]
    best = np.minimum.accumulate(f)
    ax.semilogy(range(1, len(f) + 1), f, "o", color="#1f77b4", label="objective at each evaluation")
    ax.semilogy(range(1, len(f) + 1), best, "-", color="#d62728", label="best so far")
    ax.set_xlabel("evaluation of the objective (Jacobian runs not counted)")
    ax.set_ylabel(r"$\sum_m w_m e_m^2$")
    ax.set_title("calibration %s" % fit.plan["name"])
    ax.legend()
    fig.tight_layout()
    for ext in ("png", "pdf"):
        fig.savefig(folder / ("calibration_history." + ext))
    plt.close(fig)


def draw_errors(report, folder):
    """Train and validation errors per weighted metric, at the initial and fitted values."""
    columns = list(report["weights"])
    rows = [("train", report["train"]["initial"], report["train"]["fitted"])]
    for name, v in report["validation"]["fitted"].items():
        before = report["validation"]["initial"].get(name, {}).get("errors") or {}
        rows.append(("held out: " + name, before, v.get("errors") or {}))
    fig, axes = plt.subplots(1, len(rows), figsize=(3.2 * len(rows) + 1, 4), sharey=True, squeeze=False)
    x = np.arange(len(columns))
    for ax, (title, before, after) in zip(axes[0], rows):
        value = lambda errors, c: abs(errors.get(c)) if errors.get(c) is not None else np.nan  # noqa: E731
        ax.bar(x - 0.2, [value(before, c) for c in columns], 0.4, color="#9ecae1", label="initial")
        ax.bar(x + 0.2, [value(after, c) for c in columns], 0.4, color="#08519c", label="fitted")
        ax.set_xticks(x)
        ax.set_xticklabels([c.replace("probe.", "") for c in columns], rotation=45, ha="right", fontsize=8)
        ax.set_title(title, fontsize=10)
    axes[0][0].set_ylabel("|error| (relative)")
    axes[0][0].legend()
    fig.suptitle("calibration %s: errors per metric" % report["name"], fontsize=10)
    fig.tight_layout()
    for ext in ("png", "pdf"):
        fig.savefig(folder / ("calibration_errors." + ext))
    plt.close(fig)


def validation_errors(fit, p):
    """The validation cases at parameters @p p: {name: errors} (None for a failed run)."""
    cases = []
    for v in fit.plan["validation"]:
        s = v["settings"] + fit.settings(p)
        cases.append((fit.case_name("v_%s_" % v["name"], s), s, v["name"]))
    if not cases:
        return {}
    rows = fit.run([(n, s) for n, s, _ in cases])
    out = {}
    for n, _, name in cases:
        row = rows[n]
        out[name] = {"case": n, "status": row["status"], "reason": row["reason"], "errors": row["errors"],
                     "costs": row["costs"]}
    return out


def main():
    plan = json.loads(Path(sys.argv[1]).read_text())
    fit = Fit(plan)
    folder = fit.folder
    command = "suturesim calibrate %s" % Path(plan["calibration"]).name
    start = time.time()
    z0 = fit.to_z([q["initial"] for q in fit.parameters])
    p0 = fit.to_p(z0)  # the point run first: exp(ln p) need not give p back to the last bit
    try:
        result = least_squares(fit.fun, z0, jac=fit.jac, bounds=fit.z_bounds(), method="trf",
                               max_nfev=plan["max_evaluations"], xtol=1e-6, ftol=1e-10, gtol=1e-10)
        p = fit.to_p(result.x)
        errors, jp = standard_errors(fit, result)
        initial = fit.cache[fit.case_name("p", fit.settings(p0))]
        fitted = fit.cache[fit.case_name("p", fit.settings(p))]
        validation = {"initial": validation_errors(fit, p0), "fitted": validation_errors(fit, p)}
    except StudyFailed as e:
        print(str(e) if str(e).startswith("error:") else "error: calibrate: " + str(e), file=sys.stderr)
        return e.code if e.code in (2, 3) else 1
    report = {
        "name": plan["name"],
        "command": command,
        "optimiser": {"library": "scipy.optimize.least_squares %s" % scipy.__version__, "method": "trf",
                      "status": int(result.status), "message": result.message, "success": bool(result.success),
                      "objective_runs": int(result.nfev), "jacobians": int(result.njev or 0),
                      "difference_step": plan["difference_step"]},
        "parameters": [{"path": q["path"], "initial": q["initial"], "lower": q["lower"], "upper": q["upper"],
                        "fitted_in": "ln p" if log else "p", "fitted": float(v),
                        "standard_error": e,
                        "relative_standard_error": None if e is None else e / abs(v)}
                       for q, log, v, e in zip(fit.parameters, fit.logarithmic, p, errors)],
        "objective": {"initial": float(initial["r"] @ initial["r"]), "fitted": float(fitted["r"] @ fitted["r"])},
        "weights": {c: w for c, w in fit.weights},
        "train": {"initial": initial["errors"], "fitted": fitted["errors"], "costs_fitted": fitted["costs"]},
        "validation": validation,
        "jacobian": {"rows": fit.labels, "columns": [q["path"] for q in fit.parameters],
                     "dr_dp": jp.tolist()},
        "settings": fit.settings(p),
        "history": fit.history,
        "cases_run": sum(1 for _ in (fit.runs / "cases").iterdir()),
        "wall_seconds": time.time() - start,
    }
    (folder / "calibration.json").write_text(json.dumps(report, indent=2) + "\n")
    write_fragment(folder / "calibrated.prm", fit, p, command)
    draw_history(fit, folder)
    draw_errors(report, folder)
    print("calibrate %s: %s after %d evaluations (+%d Jacobians) in %.0f s; objective %.4g -> %.4g" %
          (plan["name"], "converged" if result.success else "stopped", result.nfev, result.njev or 0,
           time.time() - start, report["objective"]["initial"], report["objective"]["fitted"]))
    for q in report["parameters"]:
        se = "" if q["standard_error"] is None else " (standard error %.3g)" % q["standard_error"]
        print("  %s = %.6g%s" % (q["path"], q["fitted"], se))
    print("wrote %s/ (calibration.json, calibrated.prm, calibration_history and calibration_errors .png/.pdf)" % folder)
    return 0 if result.success else 3


if __name__ == "__main__":
    sys.exit(main())
