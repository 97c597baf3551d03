#!/usr/bin/python3
"""The figures of a suturesim study, from its study.json (written by `suturesim study`).

Usage: /usr/bin/python3 postprocess/study_figures.py STUDY_FOLDER

- pareto.png, pareto.pdf: the Objective's cost (log axis) against its error for every
  case; the non-dominated front drawn and its cases labelled; the 1 ms and 0.25 ms
  haptic budgets drawn when the cost is a step time; failed cases drawn as crosses at
  the top of the chart (they have no error), never dropped; the cheapest case within
  tolerance ringed, the tolerance drawn.
- stability.png, stability.pdf (when the study names stability axes): each case a cell
  stable / diverged / inaccurate, with the program's predicted boundary dt = dt_crit;
  one map per value of the study's other axes (its panels), side by side.
- map.png, map.pdf (when the study names map axes and metrics): per metric (and panel) a
  heat map of the cases' own values over the two axes, with the references' values and
  the relative difference beside it when each cell has its own reference; cells without
  a value are grey ("none": no onset within the run), flagged cells hatched (e.g. seed
  003's "too close to the edge"), a run that did not complete (a case, or a reference
  kept by Reference/On failure = report) with its status under the value it reached. A
  vector value (a spacing "0, 0.004, 0") is placed at its length.
- convergence.png, convergence.pdf (when the study names a convergence metric): the
  metric against h, the Richardson extrapolation with Roache's GCI as its error bar.
Run by `suturesim study` after the tables; runs by itself on an existing folder.
"""
import json
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

COLORS = {"stable": "#2a9d3f", "diverged": "#d62728", "inaccurate": "#ff9f1c"}


def save(fig, folder, stem, tight=True):
    if tight:
        fig.tight_layout()
    for ext in ("png", "pdf"):
        fig.savefig(folder / f"{stem}.{ext}", dpi=150)
    plt.close(fig)


def pareto(study, folder):
    cases = [c for c in study["cases"] if not c.get("is_reference")]
    objective = study["objective"]
    step_time = objective["cost"].startswith("step_time")
    fig, ax = plt.subplots(figsize=(10, 5))
    fig.subplots_adjust(right=0.7)
    ok = [c for c in cases if c["status"] == "completed" and c["cost"] and c["error"] is not None]
    # incomplete: the run finished, the error is measured, another metric is missing
    partial = [c for c in cases if c["status"] == "incomplete" and c["cost"] and c["error"] is not None]
    bad = [c for c in cases if c not in ok and c not in partial]
    front = sorted((c for c in ok if c["name"] in study["front"]), key=lambda c: c["cost"])
    scale = 1e3 if step_time else 1.0
    ax.scatter([c["cost"] * scale for c in ok], [c["error"] for c in ok], s=28, color="#1f77b4",
               label=f"completed ({len(ok)})", zorder=3)
    if partial:
        ax.scatter([c["cost"] * scale for c in partial], [c["error"] for c in partial], s=40,
                   facecolors="none", edgecolors=COLORS["inaccurate"], linewidths=1.5,
                   label=f"incomplete ({len(partial)}): another metric missing", zorder=3)
    key = []
    if front:
        ax.plot([c["cost"] * scale for c in front], [c["error"] for c in front], "-", color="#1f77b4",
                alpha=0.5, label="Pareto front")
        key.append("Pareto front")
    # the front's and the other cases numbered on the chart, named in a key beside it
    numbered = front + partial + bad
    for i, c in enumerate(numbered, 1):
        if c in partial:
            key.append("incomplete") if c is partial[0] else None
        if c in bad:
            key.append("not completed") if c is bad[0] else None
        key.append(f"{i:2d}: {c['name']}" + ("" if c in front else f" ({c['status']})"))
    errors = [c["error"] for c in ok + partial] or [1.0]
    top = max(errors) * 1.6 if max(errors) > 0 else 1.0
    if bad:
        costs = [(c["cost"] or 0) * scale for c in bad]
        known = [x for x in costs if x > 0] or [1.0]
        xs = [x if x > 0 else min(known) for x in costs]
        ax.scatter(xs, [top] * len(bad), marker="x", s=40, color=COLORS["diverged"],
                   label=f"failed, diverged or no error ({len(bad)})", zorder=3)
        for c, x in zip(bad, xs):
            c["_x"], c["_y"] = x / scale, top
    for i, c in enumerate(numbered, 1):
        x, y = (c["_x"], c["_y"]) if c in bad else (c["cost"], c["error"])
        ax.annotate(str(i), (x * scale, y), textcoords="offset points", xytext=(3, 4), fontsize=7,
                    weight="bold")
    fig.text(0.72, 0.5, "\n".join(key), fontsize=6, va="center", family="monospace")
    if step_time:
        for budget, label in ((1.0, "1 ms (1 kHz)"), (0.25, "0.25 ms")):
            ax.axvline(budget, color="grey", ls="--", lw=1)
            ax.text(budget, 0.98, f" {label}", fontsize=7, color="grey", va="top", rotation=90,
                    transform=ax.get_xaxis_transform())
    tolerance = objective["tolerances"].get(objective["error"])
    if tolerance:
        ax.axhline(tolerance, color="#2a9d3f", ls=":", lw=1, label=f"tolerance {tolerance:g}")
    # the cheapest adequate case, or one per reference (Reference/Per axis)
    chosen = study.get("best")
    chosen = set(chosen.values()) if isinstance(chosen, dict) else {chosen}
    best = [c for c in ok if c["name"] in chosen]
    for c in best:
        ax.scatter([c["cost"] * scale], [c["error"]], s=140, facecolors="none", edgecolors="#2a9d3f",
                   linewidths=1.5, label=f"cheapest within tolerance: {c['name']}"
                   + (f" ({c['reference']})" if len(chosen) > 1 else ""), zorder=4)
    ax.set_xscale("log")
    shown = [c["error"] for c in ok + partial if c["error"] > 0]
    if shown and max(shown) / min(shown) > 20:
        ax.set_yscale("log")
    unit = "ms" if step_time else "s"
    ax.set_xlabel(f"{objective['cost'].replace('_', ' ')} [{unit}]")
    ax.set_ylabel(f"|{objective['error']}| error [1]")
    references = len(study["cases"]) - len(cases)
    ax.set_title(f"study {study['name']}: {len(cases)} cases against "
                 + ("the reference" if references == 1 else f"{references} references"), fontsize=10)
    ax.legend(fontsize=7, loc="best")
    ax.grid(True, which="both", alpha=0.3)
    save(fig, folder, "pareto", tight=False)


def numeric(values):
    try:
        return [float(v) for v in values], True
    except ValueError:
        return list(values), False


def predicted_boundary(xs, ys, cells):
    """Per row of a map, the x where dt = dt_crit (dt grows or falls with x)."""
    boundary = []
    for y in sorted(set(ys)):
        row = [(x, c) for x, yy, c in zip(xs, ys, cells) if yy == y and c["dt"] and c["dt_crit"]]
        if len(row) < 2:
            continue
        (x0, c0), (x1, c1) = min(row, key=lambda r: r[0]), max(row, key=lambda r: r[0])
        growing = c1["dt"] > c0["dt"]
        x, c = row[0]
        boundary.append((x * c["dt_crit"] / c["dt"] if growing else x * c["dt"] / c["dt_crit"], y))
    return boundary


def stability_panel(ax, s, cells, title):
    xs, x_num = numeric([c["x"] for c in cells])
    ys, y_num = numeric([c["y"] for c in cells])
    for state, color in COLORS.items():
        pts = [(x, y) for x, y, c in zip(xs, ys, cells) if c["state"] == state]
        if pts:
            ax.scatter([p[0] for p in pts], [p[1] for p in pts], marker="s", s=60, color=color,
                       label=state)
    other = [(x, y, c) for x, y, c in zip(xs, ys, cells) if c["state"] not in COLORS]
    if other:
        ax.scatter([p[0] for p in other], [p[1] for p in other], marker="x", s=60, color="black",
                   label="refused or crashed")
    if x_num and y_num:
        boundary = predicted_boundary(xs, ys, cells)
        if boundary:
            ax.plot([b[0] for b in boundary], [b[1] for b in boundary], "k--", lw=1.0,
                    label="predicted: dt = dt_crit")
            ax.scatter([b[0] for b in boundary], [b[1] for b in boundary], marker="|", s=400,
                       color="black", zorder=4)
        if min(xs) > 0 and max(xs) / min(xs) > 3:
            ax.set_xscale("log")
        if min(ys) > 0 and max(ys) / min(ys) > 3:
            ax.set_yscale("log")
    ax.set_xlabel(f"{s['x']} [{s['x_unit'] or '-'}]")
    ax.set_ylabel(f"{s['y']} [{s['y_unit'] or '-'}]")
    ax.set_title(title, fontsize=9)
    ax.grid(True, which="both", alpha=0.3)


def stability(study, folder):
    """One map per panel (the values of the study's other axes), side by side."""
    s = study["stability"]
    panels = list(dict.fromkeys(c.get("panel", "") for c in s["cells"]))
    fig, axes = plt.subplots(1, len(panels), figsize=(2 + 5.5 * len(panels), 5), squeeze=False,
                             sharey=True)
    for ax, panel in zip(axes[0], panels):
        cells = [c for c in s["cells"] if c.get("panel", "") == panel]
        # "Suture/Cross section/Young's modulus = 1e9" -> "Young's modulus = 1e9"
        title = ", ".join(part.split("/")[-1] for part in panel.split(", "))
        stability_panel(ax, s, cells, title)
    handles = {}
    for ax in axes[0]:
        for h, label in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(label, h)
    fig.suptitle(f"study {study['name']}: stability map", fontsize=10)
    fig.legend(handles.values(), handles.keys(), fontsize=7, loc="lower center", ncol=5)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    save(fig, folder, "stability", tight=False)


def axis_key(value):
    """An axis value as a number (a scalar, or a vector's length), else as its text."""
    try:
        parts = [float(p) for p in str(value).split(",")]
    except ValueError:
        return str(value)
    return parts[0] if len(parts) == 1 else math.sqrt(sum(p * p for p in parts))


def axis_grid(values):
    """The map's positions along an axis: numbers in order, else the values as they come."""
    keys = list(dict.fromkeys(axis_key(v) for v in values))
    if all(isinstance(k, float) for k in keys):
        keys.sort()
    return keys


HATCHES = ["///", "\\\\\\", "xx", "..", "++"]


def map_panel(ax, cells, xs, ys, values, flags, title, unit, cmap, limits=None, statuses=None):
    """A heat map of values[i] (None: grey) on the grid xs × ys; flagged cells hatched; a
    run that did not complete (statuses[i]) has its status under its value."""
    grid = np.full((len(ys), len(xs)), np.nan)
    for c, v in zip(cells, values):
        if v is not None:
            grid[ys.index(axis_key(c["y"])), xs.index(axis_key(c["x"]))] = v
    masked = np.ma.masked_invalid(grid)
    colormap = plt.get_cmap(cmap).copy()
    colormap.set_bad("#cccccc")
    lo, hi = limits if limits else (np.nanmin(grid) if np.isfinite(grid).any() else 0,
                                    np.nanmax(grid) if np.isfinite(grid).any() else 1)
    image = ax.imshow(masked, origin="lower", cmap=colormap, vmin=lo, vmax=hi, aspect="auto")
    for k, (c, v) in enumerate(zip(cells, values)):
        i, j = ys.index(axis_key(c["y"])), xs.index(axis_key(c["x"]))
        text = "none" if v is None else f"{v:.3g}"
        status = statuses[k] if statuses else "completed"
        ax.text(j, i, text if status in ("completed", "") else f"{text}\n({status})", ha="center", va="center",
                fontsize=6)
        for name, hatch in flags:
            if (c["flags"].get(name) or 0) > 0:
                ax.add_patch(plt.Rectangle((j - 0.5, i - 0.5), 1, 1, fill=False, hatch=hatch, edgecolor="black",
                                           lw=0, alpha=0.5))
    label = lambda k: f"{k:g}" if isinstance(k, float) else k  # noqa: E731
    ax.set_xticks(range(len(xs)), [label(x) for x in xs], fontsize=7)
    ax.set_yticks(range(len(ys)), [label(y) for y in ys], fontsize=7)
    ax.set_title(title, fontsize=8)
    plt.colorbar(image, ax=ax, label=unit, shrink=0.85)


def study_map(study, folder):
    """Per metric and panel: the cases' values, the references' and their difference."""
    m = study["map"]
    panels = list(dict.fromkeys(c["panel"] for c in m["cells"]))
    rows = [(metric["case"], metric["reference"], panel) for metric in m["metrics"] for panel in panels]
    with_reference = m["references_per_cell"] and any(
        v is not None for c in m["cells"] for v in c["reference_values"].values())
    columns = 3 if with_reference else 1
    fig, axes = plt.subplots(len(rows), columns, figsize=(1 + 5 * columns, 0.5 + 4 * len(rows)), squeeze=False)
    flags = [(f, HATCHES[k % len(HATCHES)]) for k, f in enumerate(m["flags"])]
    for (metric, reference, panel), row in zip(rows, axes):
        cells = [c for c in m["cells"] if c["panel"] == panel]
        xs = axis_grid(c["x"] for c in cells)
        ys = axis_grid(c["y"] for c in cells)
        own = [c["values"][metric] for c in cells]
        where = f" ({panel})" if panel else ""
        if not with_reference:
            map_panel(row[0], cells, xs, ys, own, flags, f"{metric}{where}", metric, "viridis")
            continue
        ref = [c["reference_values"][reference] for c in cells]
        both = [v for v in own + ref if v is not None] or [0, 1]
        limits = (min(both), max(both))
        own_status = [c["status"] for c in cells]
        ref_status = [c.get("reference_status", "completed") for c in cells]
        map_panel(row[0], cells, xs, ys, own, flags, f"cases: {metric}{where}", metric, "viridis", limits,
                  own_status)
        map_panel(row[1], cells, xs, ys, ref, flags, f"references: {reference}{where}", reference, "viridis",
                  limits, ref_status)
        # none against a reference that stopped early: what it holds is its last converged
        # state's, which an end-of-run metric does not mean (its panel shows it, marked)
        difference = [None if a is None or b in (None, 0) or st not in ("completed", "") else (a - b) / abs(b)
                      for a, b, st in zip(own, ref, ref_status)]
        spread = max([abs(d) for d in difference if d is not None] or [1])
        map_panel(row[2], cells, xs, ys, difference, flags, "(case − reference) / |reference|", "1", "RdBu_r",
                  (-spread, spread), ref_status)
    for ax in axes.flat:
        ax.set_xlabel(f"{m['x']} [{m['x_unit'] or '-'}]", fontsize=7)
        ax.set_ylabel(f"{m['y']} [{m['y_unit'] or '-'}]", fontsize=7)
    if flags:
        handles = [plt.Rectangle((0, 0), 1, 1, fill=False, hatch=h, label=f"{f} > 0") for f, h in flags]
        fig.legend(handles=handles, fontsize=7, loc="lower center", ncol=len(handles))
    fig.suptitle(f"study {study['name']}: map", fontsize=10)
    # room for the title above the first row's panel titles (half an inch)
    fig.tight_layout(rect=(0, 0.05 if flags else 0, 1, 1 - 0.5 / fig.get_figheight()))
    save(fig, folder, "map", tight=False)


def convergence(study, folder):
    c = study["convergence"]
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    hmax = 0
    # a series is named by its parameter's value: with the parameter, unless it is the
    # model path, whose values name themselves ("accurate", "realtime")
    parameter = c.get("series_parameter") or ""
    named = (lambda v: f"{parameter} = {v}") if parameter and parameter != "Model" else (lambda v: v)
    for k, series in enumerate(c["series"]):
        table = [r for r in series["table"] if r["value"] is not None and r["h"] is not None]
        if not table:
            continue
        color = f"C{k}"
        hmax = max(hmax, max(r["h"] for r in table))
        ax.plot([r["h"] for r in table], [r["value"] for r in table], "o-", color=color,
                label=named(series["series"]))
        if series.get("extrapolated") is not None:
            f1 = min(table, key=lambda r: r["h"])["value"]
            bar = abs(series["gci_fine"] * f1)
            ax.errorbar([0], [series["extrapolated"]], yerr=[bar], fmt="s", color=color, capsize=4,
                        label=f"{named(series['series'])}: Richardson, p = {series['observed_order']:.2f}, "
                              f"GCI {100 * series['gci_fine']:.2g} %"
                              + (" (oscillatory: not asymptotic)" if series.get("oscillatory") else "")
                              + (" (diverging: not asymptotic)" if series.get("diverging") else ""))
    measured = str(c.get("h", "")).startswith("measured")
    ax.set_xlabel("cell size h = (V/N)^(1/3) [m]" if measured else "h [m]")
    ax.set_ylabel(c["metric"])
    ax.set_xlim(left=-0.05 * hmax)
    ax.set_title(f"study {study['name']}: convergence", fontsize=10)
    ax.legend(fontsize=7)
    ax.grid(True, alpha=0.3)
    save(fig, folder, "convergence")


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    folder = Path(sys.argv[1])
    with open(folder / "study.json") as f:
        study = json.load(f)
    if study["objective"]["error"]:
        pareto(study, folder)
    if study.get("stability"):
        stability(study, folder)
    if study.get("map"):
        study_map(study, folder)
    if study.get("convergence"):
        convergence(study, folder)


if __name__ == "__main__":
    main()
