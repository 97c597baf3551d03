#!/usr/bin/python3
"""Plot a run's forces.csv; for needle scenes also the needle force curves.

Usage: /usr/bin/python3 postprocess/plot_forces.py OUTPUT_DIR [OUTPUT_DIR ...] [--out FIGURE]

Every column of the first run's forces.csv against time, one panel per quantity, into
FIGURE (default OUTPUT_DIR/forces.png). The header names each column with its unit in
brackets; columns are grouped by name without the trailing _x/_y/_z.

Runs with a needle (columns needle_force_*, events in summary.json) also get
needle_forces.png and needle_forces.pdf in the first run's folder: the needle force
magnitude against time with the puncture events marked, and the pull force (the needle
force after the turn) against the pulled length (the needle's travel since the turn
ended). Several runs (e.g. the accurate and the realtime output of one scene) are
overlaid, labelled by model.
"""
import csv
import json
import math
import sys
from collections import OrderedDict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(run):
    with open(run / "forces.csv") as f:
        rows = list(csv.reader(f))
    header, data = rows[0], [[float(v) for v in r] for r in rows[1:]]
    if not data:
        sys.exit(f"{run}/forces.csv has no rows")
    return header, data


def column(header, data, name):
    for i, h in enumerate(header):
        if h.split(" ", 1)[0] == name:
            return [r[i] for r in data]
    return None


def save(fig, folder, stem):
    """Writes fig as <folder>/<stem>.png and .pdf and closes it."""
    fig.tight_layout()
    for suffix in ("png", "pdf"):
        out = folder / f"{stem}.{suffix}"
        fig.savefig(out, dpi=150)
        print(out)
    plt.close(fig)


def plot_columns(run, figure):
    header, data = read(run)
    time = [r[0] for r in data]
    groups = OrderedDict()
    for i, name in enumerate(header[1:], start=1):
        label, unit = name.split(" ", 1)
        base, component = label.rsplit("_", 1) if "_" in label else (label, label)
        groups.setdefault((base, unit), []).append((component, i))
    fig, axes = plt.subplots(len(groups), 1, figsize=(6, 2.4 * len(groups)), sharex=True,
                             squeeze=False)
    for ax, ((base, unit), columns) in zip(axes[:, 0], groups.items()):
        for component, i in columns:
            ax.plot(time, [r[i] for r in data], marker=".", markersize=2, label=component)
        ax.set_ylabel(f"{base} {unit}")
        ax.legend(loc="best", fontsize="small")
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel(header[0])
    fig.tight_layout()
    fig.savefig(figure, dpi=120)
    plt.close(fig)
    print(figure)


def plot_needle(runs):
    fig, (ax_t, ax_pull) = plt.subplots(2, 1, figsize=(7, 7))
    for run in runs:
        header, data = read(run)
        fx = column(header, data, "needle_force_x")
        if fx is None:
            continue
        summary = json.load(open(run / "summary.json"))
        fy, fz = column(header, data, "needle_force_y"), column(header, data, "needle_force_z")
        time = [r[0] for r in data]
        force = [math.sqrt(a * a + b * b + c * c) for a, b, c in zip(fx, fy, fz)]
        label = f"{summary.get('model', '?')} ({run.name})"
        line = ax_t.plot(time, force, label=label)[0]
        for e in summary.get("events", []):
            if e["kind"].startswith("puncture"):
                ax_t.axvline(e["time"], color=line.get_color(), ls=":", lw=1)
                ax_t.annotate(e["kind"].replace("puncture_", "puncture\n") + f"\n{e['force']:.2f} N",
                              (e["time"], e["force"]), textcoords="offset points", xytext=(4, 4),
                              fontsize="x-small", color=line.get_color())
        t_pull = summary.get("needle", {}).get("pass", {}).get("t_turn_end")
        centre = [column(header, data, f"needle_centre_{c}") for c in "xyz"]
        if t_pull is not None and centre[0] is not None:
            k0 = next(i for i, t in enumerate(time) if t >= t_pull)
            c0 = [c[k0] for c in centre]
            length = [math.dist([c[i] for c in centre], c0) for i in range(k0, len(time))]
            ax_pull.plot([1e3 * v for v in length], force[k0:], label=label)
    ax_t.set_xlabel("time [s]")
    ax_t.set_ylabel("needle force |F| [N]")
    ax_t.grid(alpha=0.3)
    ax_t.legend(fontsize="small")
    ax_pull.set_xlabel("pulled length [mm]")
    ax_pull.set_ylabel("pull force |F| [N]")
    ax_pull.grid(alpha=0.3)
    if ax_pull.lines:
        ax_pull.legend(fontsize="small")
    save(fig, runs[0], "needle_forces")


def main():
    args = sys.argv[1:]
    figure = None
    if "--out" in args:
        k = args.index("--out")
        figure = Path(args[k + 1])
        del args[k : k + 2]
    if not args:
        sys.exit(__doc__)
    runs = [Path(a) for a in args]
    plot_columns(runs[0], figure or runs[0] / "forces.png")
    header, _ = read(runs[0])
    if any(h.startswith("needle_force_x") for h in header):
        plot_needle(runs)


if __name__ == "__main__":
    main()
