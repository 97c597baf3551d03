#!/usr/bin/python3
"""Plot every column of a run's forces.csv against time, one panel per quantity.

Usage: /usr/bin/python3 postprocess/plot_forces.py OUTPUT_DIR [FIGURE.png]
The header of forces.csv names each column with its unit in brackets; columns are
grouped by name without the trailing _x/_y/_z.
"""
import csv
import sys
from collections import OrderedDict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    run = Path(sys.argv[1])
    figure = Path(sys.argv[2]) if len(sys.argv) > 2 else run / "forces.png"
    with open(run / "forces.csv") as f:
        rows = list(csv.reader(f))
    header, data = rows[0], [[float(v) for v in r] for r in rows[1:]]
    if not data:
        sys.exit(f"{run}/forces.csv has no rows")
    time = [r[0] for r in data]
    groups = OrderedDict()
    for i, name in enumerate(header[1:], start=1):
        label, unit = name.rsplit(" ", 1)
        base, component = label.rsplit("_", 1)
        groups.setdefault((base, unit), []).append((component, i))
    fig, axes = plt.subplots(len(groups), 1, figsize=(6, 2.4 * len(groups)), sharex=True,
                             squeeze=False)
    for ax, ((base, unit), columns) in zip(axes[:, 0], groups.items()):
        for component, i in columns:
            ax.plot(time, [r[i] for r in data], marker=".", label=component)
        ax.set_ylabel(f"{base} {unit}")
        ax.legend(loc="best", fontsize="small")
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel(header[0])
    fig.tight_layout()
    fig.savefig(figure, dpi=120)
    print(figure)


if __name__ == "__main__":
    main()
