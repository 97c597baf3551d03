#!/usr/bin/env python3
"""Force and closure curves of stitch runs (issue 6), several runs overlaid:

  /usr/bin/python3 postprocess/plot_stitch.py output/stitch_interrupted [more runs...]

writes stitch_curves.png and .pdf into the first run's folder with three panels:
needle force vs time with the puncture events (closure dashed, tie-off dash-dotted),
suture tension (at the grasped tail) vs the length the needle end has been drawn since
its turn ended, and the wound gap (first closure pair) vs that tension.
"""
import json
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from plot_forces import column, read, save  # noqa: E402


def magnitude(header, data, base):
    parts = [column(header, data, f"{base}_{c}") for c in "xyz"]
    if parts[0] is None:
        return None
    return [math.sqrt(a * a + b * b + c * c) for a, b, c in zip(*parts)]


def main():
    runs = [Path(a) for a in sys.argv[1:]]
    if not runs:
        sys.exit(__doc__)
    fig, (ax_t, ax_pull, ax_gap) = plt.subplots(3, 1, figsize=(7, 10))
    for run in runs:
        header, data = read(run)
        summary = json.load(open(run / "summary.json"))
        label = f"{summary.get('model', '?')} ({run.name})"
        time = [r[0] for r in data]
        needle = magnitude(header, data, "needle_force")
        if needle is None:
            sys.exit(f"{run}: no needle columns in forces.csv")
        line = ax_t.plot(time, needle, label=label)[0]
        for e in summary.get("events", []):
            if e["kind"].startswith("puncture"):
                ax_t.axvline(e["time"], color=line.get_color(), ls=":", lw=1)
        closure = summary["metrics"].get("closure_time")
        if closure is not None:
            ax_t.axvline(closure, color=line.get_color(), ls="--", lw=1)
            ax_t.annotate("closed", (closure, 0.02), xycoords=ax_t.get_xaxis_transform(),
                          fontsize="x-small", color=line.get_color(), ha="right")
        tied = summary["metrics"].get("tie_off_time")
        if tied is not None and tied != closure:
            ax_t.axvline(tied, color=line.get_color(), ls="-.", lw=1)
            ax_t.annotate("tied", (tied, 0.08), xycoords=ax_t.get_xaxis_transform(),
                          fontsize="x-small", color=line.get_color(), ha="left")
        tension = magnitude(header, data, "suture_end_force") or needle
        t_pull = summary.get("needle", {}).get("pass", {}).get("t_turn_end", 0)
        centre = [column(header, data, f"needle_centre_{c}") for c in "xyz"]
        k0 = next(i for i, t in enumerate(time) if t >= t_pull)
        c0 = [c[k0] for c in centre]
        drawn = [1e3 * math.dist([c[i] for c in centre], c0) for i in range(k0, len(time))]
        ax_pull.plot(drawn, tension[k0:], label=label)
        gap_name = next((h.split(" ")[0] for h in header if h.startswith("gap_")), None)
        if gap_name is not None:
            gap = column(header, data, gap_name)
            ax_gap.plot(tension, [1e3 * g for g in gap], label=f"{label}, {gap_name}")
            limit = summary["metrics"].get("closure_gap")
            if limit is not None:
                ax_gap.axhline(1e3 * limit, color="grey", ls=":", lw=1)
    ax_t.set_xlabel("time [s]")
    ax_t.set_ylabel("needle force |F| [N]")
    ax_pull.set_xlabel("needle end drawn since the turn [mm]")
    ax_pull.set_ylabel("suture tension at the tail [N]")
    ax_gap.set_xlabel("suture tension at the tail [N]")
    ax_gap.set_ylabel("wound gap [mm]")
    for ax in (ax_t, ax_pull, ax_gap):
        ax.grid(alpha=0.3)
        if ax.lines:
            ax.legend(fontsize="small")
    save(fig, runs[0], "stitch_curves")


if __name__ == "__main__":
    main()
