#!/usr/bin/python3
"""Cantilever under a tip force of fixed direction (PL^2/EI = 3) against the elastica
(reference.json: published table, stored elastica, tolerances).

  /usr/bin/python3 benchmarks/rod_cantilever/compare.py OUTPUT --run build/suturesim
  /usr/bin/python3 benchmarks/rod_cantilever/compare.py OUTPUT   # OUTPUT/rod_cantilever there

Solves the elastica by shooting (RK4 + bisection) for the run's PL^2/EI, checks it
against Mattiasson's published table and the stored value, prints the run's tip against
it; draws OUTPUT/rod_cantilever.png/.pdf (the rod and the elastica); exits 1 when the
issue-3 acceptance or the regression tolerance is exceeded.
"""
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent.parent / "postprocess"))
import benchlib  # noqa: E402
import vtu  # noqa: E402


def elastica(k, steps=4000):
    """Inextensible elastica, L = EI = 1, tip force k along -y: theta'' = k cos(theta),
    theta(0) = 0, theta'(1) = 0. Returns the centreline (steps + 1, 2)."""
    def f(z):
        return np.array([z[1], k * math.cos(z[0]), math.cos(z[0]), math.sin(z[0])])

    def shoot(kappa0):
        s, h, path = np.array([0.0, kappa0, 0.0, 0.0]), 1.0 / steps, []
        for _ in range(steps):
            path.append(s[2:].copy())
            k1 = f(s); k2 = f(s + 0.5 * h * k1); k3 = f(s + 0.5 * h * k2); k4 = f(s + h * k3)
            s = s + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        path.append(s[2:].copy())
        return s[1], np.array(path)

    lo, hi = -k, 0.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if shoot(mid)[0] > 0:
            hi = mid
        else:
            lo = mid
    return shoot(0.5 * (lo + hi))[1]


def main():
    args = benchlib.arguments(__doc__).parse_args()
    ref = benchlib.reference(__file__)
    run = Path(args.output) / "rod_cantilever"
    if args.run:
        benchlib.run(args.run, benchlib.folder_of(__file__) / ref["scene"], run)
    prm = benchlib.parameters(run)
    L = float(prm["Suture/Straight/Length"])
    r = float(prm["Suture/Cross section/Radius"])
    E = float(prm["Suture/Cross section/Young's modulus"])
    P = abs(float(prm["Suture/Loads/End force"].split(",")[1]))
    k = P * L ** 2 / (E * math.pi * r ** 4 / 4)
    failures = []

    published = ref["published"]
    rows = []
    for i, kp in enumerate(published["load_PL2_over_EI"]):
        x, y = elastica(kp)[-1]
        rows.append([f"{kp:g}", f"{-y:.7f}", f"{published['w_over_L'][i]:.5f}", f"{1 - x:.7f}", f"{published['u_over_L'][i]:.5f}"])
        if max(abs(-y - published["w_over_L"][i]), abs(1 - x - published["u_over_L"][i])) > published["tolerance"]:
            failures.append(f"shooting at PL^2/EI = {kp:g} off the published table")
    print("shooting against Mattiasson (1981), Table 1:")
    benchlib.table(["PL^2/EI", "w/L shooting", "w/L published", "u/L shooting", "u/L published"], rows)

    line = elastica(k)
    stored = ref["elastica"]
    if abs(k - stored["load_PL2_over_EI"]) > 1e-6 or max(abs(line[-1][0] - stored["x_over_L"]),
                                                         abs(line[-1][1] - stored["y_over_L"])) > stored["tolerance"]:
        failures.append(f"the scene's PL^2/EI = {k:.7f} or its elastica differs from reference.json")
    tip = np.array(benchlib.summary(run)["metrics"]["tip_position"])
    y_ref = stored["y_over_L"] * L
    error = abs(tip[1] - y_ref) / abs(y_ref)
    regression = np.array(ref["regression"]["tip_m"])
    drift = np.max(np.abs(tip[:2] - regression))
    acceptance, tolerance = ref["acceptance"]["relative_tip_deflection"], ref["regression"]["tolerance_m"]
    print(f"\nscene: PL^2/EI = {k:.6f}, L = {L} m, {prm['Suture/Elements']} elements")
    benchlib.table(["quantity", "suturesim", "reference", "difference", "tolerance (source)"], [
        ["tip y [m]", f"{tip[1]:.8e}", f"{y_ref:.7e} (elastica)", f"{100 * error:.4f} %", f"{100 * acceptance:g} % ({ref['acceptance']['source']})"],
        ["tip (x, y) [m]", f"({tip[0]:.10e}, {tip[1]:.10e})", "regression value", f"{drift:.2e} m",
         f"{tolerance:g} m (100 x the measured spread {ref['regression']['measured_spread_m']:g} m)"],
    ])
    if error > acceptance:
        failures.append(f"tip deflection {100 * error:.4f} % off the elastica > {100 * acceptance:g} %")
    if drift > tolerance:
        failures.append(f"tip {drift:.3e} m from the regression value > {tolerance:g} m")
    if not args.no_figure:
        figure(run, line, L, Path(args.output) / "rod_cantilever")
    benchlib.verdict(failures)


def figure(run, line, L, stem):
    plt = benchlib.pyplot()
    fig, ax = plt.subplots(figsize=(4.5, 3.5))
    ax.plot(1e3 * L * line[:, 0], 1e3 * L * line[:, 1], "k-", lw=3, alpha=0.3, label="elastica (shooting)")
    for t, path in vtu.series(str(run / "suture.pvd")):
        p = vtu.read(path)[0]
        ax.plot(1e3 * p[:, 0], 1e3 * p[:, 1], "-", lw=1, color=plt.cm.viridis(t), label=f"suturesim, load {t:.1f}")
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1))
    benchlib.save_figure(fig, stem)


if __name__ == "__main__":
    main()
