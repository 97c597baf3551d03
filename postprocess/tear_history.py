#!/usr/bin/python3
"""The tear criteria's history against the pull in accurate stitch runs (issue 29 item 4:
whether a criterion's zone mean per unit load converges under refinement, apart from
the onset read off a stick-slip pull):

  /usr/bin/python3 postprocess/tear_history.py RUN [RUN ...] --from 4.6 [--out FOLDER]

Reads each run's forces.csv (pull_tension and tear_<criterion>: the largest zone mean
over the critical value per state, written with Tearing/Criteria) and summary.json
(metrics.tearing). For every criterion it fits, over the rows from --from (s) up to the
criterion's onset, the zone mean's growth with the pull tension T as a power of it,
  m = k T^p,   p = 2 for the energy criteria (Psi grows with the square of a load),
  p = 1 for the stress, and for the stretch criterion lambda - 1 = k T,
by least squares through the origin, and prints k, the fit's rms misfit and the tension
T* at which the fitted law reaches the critical value, next to the onset tension the
run read. Writes tear_history.png and .pdf into FOLDER (default: the first run's folder):
one panel per criterion, the zone mean against T after --from.
"""
import argparse
import csv
import json
import sys
from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

POWER = {"fracture-energy": 2, "strain-energy-density": 2, "max-principal-stress": 1, "max-principal-stretch": 1}


def fail(message):
    """Bad input: one line naming what, exit 2 (as suturesim's own input errors)."""
    print("tear_history.py: " + message, file=sys.stderr)
    sys.exit(2)


def read(run):
    try:
        with open(run / "forces.csv") as f:
            rows = list(csv.reader(f))
        header = rows[0]
        data = np.array([[float(x) for x in r] for r in rows[1:]])
        tearing = json.loads((run / "summary.json").read_text())["metrics"]["tearing"]
    except OSError as e:
        fail("cannot read %s: %s" % (e.filename, e.strerror))
    except (IndexError, ValueError, KeyError) as e:
        fail("%s: not a run with Tearing/Criteria (forces.csv and summary.json's metrics.tearing): %s" % (run, e))
    if "pull_tension [N]" not in header:
        fail("%s/forces.csv has no pull_tension (a run without Tearing/Criteria, or older than the column)" % run)
    return header, data, tearing


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", type=Path)
    parser.add_argument("--from", dest="start", type=float, required=True,
                        help="first time of the fit (s): the pull whose growth is measured")
    parser.add_argument("--out", type=Path)
    args = parser.parse_args()
    runs = [(run, *read(run)) for run in args.runs]
    names = [n for n in POWER if all("tear_%s [1]" % n in h for _, h, _, _ in runs)]
    if not names:
        fail("the runs share no criterion")
    fig, axes = plt.subplots(1, len(names), figsize=(4 * len(names), 3.5), squeeze=False)
    print("| run | criterion | k | rms misfit | T* (N) | onset tension (N) |")
    print("|---|---|---|---|---|---|")
    for run, header, data, tearing in runs:
        t, T = data[:, 0], data[:, header.index("pull_tension [N]")]
        for ax, name in zip(axes[0], names):
            criterion = tearing["criteria"][name]
            ratio = data[:, header.index("tear_%s [1]" % name)]
            onset = criterion.get("onset_time", np.inf)
            shown = t >= args.start
            ax.plot(T[shown], ratio[shown], ".", ms=3, label=run.name)
            fit = shown & (t < onset) & np.isfinite(ratio) & (T > 0)
            p = POWER[name]
            # the stretch criterion's ratio is lambda / lambda_c: its growth is lambda - 1
            critical = criterion["critical_value"] - 1 if name == "max-principal-stretch" else 1.0
            y = ratio[fit] * criterion["critical_value"] - 1 if name == "max-principal-stretch" else ratio[fit]
            A = T[fit] ** p
            if fit.sum() < 3:
                print("| %s | %s | (fewer than 3 rows) | | | |" % (run.name, name))
                continue
            k = A @ y / (A @ A)
            misfit = np.sqrt(np.mean((y - k * A) ** 2) / np.mean(y ** 2))
            onset_tension = criterion.get("onset_tension")
            print("| %s | %s | %.4g | %.1f %% | %.3f | %s |" % (
                run.name, name, k, 100 * misfit, (critical / k) ** (1 / p),
                "%.3f" % onset_tension if onset_tension is not None else "none"))
    for ax, name in zip(axes[0], names):
        ax.axhline(1, color="k", lw=0.5)
        ax.set_title(name)
        ax.set_xlabel("pull tension (N)")
        ax.set_ylabel("largest zone mean / critical")
    axes[0][0].legend()
    fig.tight_layout()
    out = args.out or args.runs[0]
    try:
        out.mkdir(parents=True, exist_ok=True)
        for suffix in ("png", "pdf"):
            fig.savefig(out / ("tear_history." + suffix))
    except OSError as e:
        fail("cannot write %s: %s" % (out / "tear_history.png", e.strerror))


if __name__ == "__main__":
    main()
