#!/usr/bin/python3
"""Tightening curves of knot specimens (Bodies = knot specimen; forces.csv):
left, the scaled end force F h^2/B against eps = sqrt(h/R) with the law of Audoly,
Clauvelin & Neukirch (PRL 99, 164301, 2007), eps^4/2 + mu sigma eps^3, for the overhand
knots (the runs whose forces.csv has the law's column; a figure-eight's has none);
right, the end force against the end shortening e.

Usage: /usr/bin/python3 postprocess/plot_knot_tightening.py OUTPUT_DIR [OUTPUT_DIR ...] [--out FIGURE]

FIGURE defaults to OUTPUT_DIR/knot_tightening.png (a .pdf is written beside it). Each
run's friction coefficient is read back from its law column, so the law is drawn for it.
"""
import csv
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from figure import save_png_and_pdf  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SIGMA = 0.492  # the trefoil's friction constant (Audoly et al. 2007)


def load(run):
    """The run's forces.csv as a dict of columns (names without units)."""
    path = run / "forces.csv"
    if not path.is_file():
        sys.exit(f"{path} not found (a run with Bodies = knot specimen writes it)")
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if len(rows) < 2:
        sys.exit(f"{path} has no rows")
    values = np.array(rows[1:], float)
    return {name.split(" [")[0]: values[:, k] for k, name in enumerate(rows[0])}


def friction(c):
    """mu from the law column: (law - eps^4/2) / (sigma eps^3)."""
    mu = (c["audoly_force_scaled"] - 0.5 * c["eps"] ** 4) / (SIGMA * c["eps"] ** 3)
    return float(np.median(mu))


def main(argv):
    out = None
    if "--out" in argv:
        i = argv.index("--out")
        if i + 1 >= len(argv):
            sys.exit("--out needs a file name")
        out = Path(argv[i + 1])
        argv = argv[:i] + argv[i + 2:]
    runs = [Path(a) for a in argv]
    if not runs:
        sys.exit(__doc__)
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.3))
    eps_max = 0
    for k, run in enumerate(runs):
        c = load(run)
        colour = f"C{k}"
        label = run.name
        if "audoly_force_scaled" in c:
            mu = friction(c)
            label = f"{run.name}, $\\mu$ = {mu:.2g}"
            eps = np.linspace(0, 1.05 * c["eps"].max(), 200)
            left.plot(eps, 0.5 * eps ** 4 + mu * SIGMA * eps ** 3, "-", color=colour, lw=1,
                      label=f"Audoly et al. 2007, $\\mu$ = {mu:.2g}")
        left.plot(c["eps"], c["force_scaled"], "o", ms=4, color=colour, label=label)
        right.plot(c["shortening"] * 1e3, c["force"], "o-", ms=3, color=colour, label=label)
        eps_max = max(eps_max, c["eps"].max())
    left.set_xlim(0, 1.05 * eps_max)
    left.set_xlabel(r"$\varepsilon = \sqrt{h/R}$")
    left.set_ylabel(r"$F h^2 / B$")
    left.legend(fontsize=8)
    left.set_title("scaled end force against the braid's exit curvature")
    right.set_xlabel("end shortening e = L - |x_N - x_0| [mm]")
    right.set_ylabel("end force F [N]")
    right.invert_xaxis()
    right.legend(fontsize=8)
    right.set_title("tightening curve (pulled: e falls)")
    save_png_and_pdf(fig, out or runs[0] / "knot_tightening.png")


if __name__ == "__main__":
    main(sys.argv[1:])
