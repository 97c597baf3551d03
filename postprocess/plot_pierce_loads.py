#!/usr/bin/python3
"""The pierce points' loads of stitch runs side by side (issue 28: where the two model
paths' closure tensions part):

  /usr/bin/python3 postprocess/plot_pierce_loads.py RUN [RUN ...] [--out FOLDER]

Reads each run's forces.csv (pierce_<i>_normal_force, pierce_<i>_friction_force,
suture_tension_swage, suture_tension_free_end, needle_force_*) and summary.json
(metrics.closure_time). Writes pierce_loads.png and .pdf into FOLDER (default: the
first run's folder), three panels against time: each hole's normal force, each hole's
friction (on the tissue point, along the thread towards its free end), and the thread's
tension at both ends with the needle force. Prints, at each run's closure, the balance
along the thread as a Markdown table: tension change from the swage to the free end
against the friction summed over the holes; for a thread without bending stiffness the
two are equal (their difference is what the thread's bending and shear carry). With
the runs' suture.pvd, the table also has the thread's tension in each of its sections
between holes, in thread order from the swage (the section between the wound's two
faces is the one that closes it), interpolated in time between the two written states
that bracket the closure. The holes' thread coordinates ζ (pierce_<i>_anchor) count
from the needle's tip; --arc gives the needle's arc length R Φ (m; default 0.008 · 3π/4,
the shipped 3/8 needle of R = 8 mm) that ζ − R Φ is the suture's own coordinate.
"""
import json
import math
import sys
from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from plot_forces import column, read, save  # noqa: E402
from plot_stitch import magnitude  # noqa: E402
import vtu  # noqa: E402


def holes(header):
    """Indices i of the pierce_<i>_normal_force columns, in order."""
    found = []
    for h in header:
        name = h.split(" ", 1)[0]
        if name.startswith("pierce_") and name.endswith("_normal_force"):
            found.append(int(name.split("_")[1]))
    return sorted(found)


def at(time, values, t):
    """The value at the recorded time nearest @p t."""
    k = min(range(len(time)), key=lambda i: abs(time[i] - t))
    return values[k]


def load(run):
    header, data = read(run)
    summary = json.load(open(run / "summary.json"))
    time = [r[0] for r in data]
    needle = magnitude(header, data, "needle_force")
    if needle is None:
        sys.exit(f"{run}: forces.csv has no needle_force columns")
    series = {
        "time": time,
        "needle": needle,
        "swage": column(header, data, "suture_tension_swage"),
        "free": column(header, data, "suture_tension_free_end"),
        "normal": {i: column(header, data, f"pierce_{i}_normal_force") for i in holes(header)},
        "friction": {i: column(header, data, f"pierce_{i}_friction_force") for i in holes(header)},
        "anchor": {i: column(header, data, f"pierce_{i}_anchor") for i in holes(header)},
    }
    if series["swage"] is None or series["free"] is None or not series["normal"]:
        sys.exit(f"{run}: forces.csv lacks the suture tensions or the pierce point columns")
    label = f"{summary.get('model', '?')} ({run.name})"
    return label, series, summary.get("metrics", {}).get("closure_time")


def thread_state(run, t):
    """(arc length (m), tension (N)) along the suture at time @p t, interpolated between
    the two written states that bracket it; None without suture.pvd."""
    pvd = run / "suture.pvd"
    if not pvd.exists():
        return None
    states = vtu.series(str(pvd))
    before = max((s for s in states if s[0] <= t), default=states[0], key=lambda s: s[0])
    after = min((s for s in states if s[0] >= t), default=states[-1], key=lambda s: s[0])
    profiles = []
    for _, path in (before, after):
        points, _, _, arrays = vtu.read(path)
        tension = arrays.get("tension", arrays.get("axial_force"))
        if tension is None:
            return None
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
        profiles.append((arc, np.asarray(tension, dtype=float).ravel()))
    w = 0.0 if after[0] == before[0] else (t - before[0]) / (after[0] - before[0])
    (a0, t0), (a1, t1) = profiles
    if len(a0) != len(a1):
        return profiles[0 if w < 0.5 else 1]
    return (1 - w) * a0 + w * a1, (1 - w) * t0 + w * t1


def section_tensions(run, s, t, arc_length):
    """The thread's tension mid-way between consecutive holes at @p t, from the swage."""
    state = thread_state(run, t)
    if state is None:
        return []
    arc, tension = state
    cuts = sorted(at(s["time"], a, t) - arc_length for a in s["anchor"].values())
    cuts = [0.0] + cuts + [arc[-1]]
    return [float(np.interp(0.5 * (lo + hi), arc, tension)) for lo, hi in zip(cuts[:-1], cuts[1:])]


def balance_row(label, s, t, sections):
    swage, free = at(s["time"], s["swage"], t), at(s["time"], s["free"], t)
    normals = [at(s["time"], v, t) for v in s["normal"].values()]
    frictions = [at(s["time"], v, t) for v in s["friction"].values()]
    return (f"| {label} | {t:.3f} s | {at(s['time'], s['needle'], t):.3f} | {swage:.3f} | {free:.3f} | "
            f"{free - swage:.3f} | {sum(frictions):.3f} | "
            + " / ".join(f"{n:.2f}" for n in normals) + " | "
            + " / ".join(f"{f:+.2f}" for f in frictions) + " | "
            + " / ".join(f"{v:.2f}" for v in sections) + " |")


def main():
    args = sys.argv[1:]
    options = {"--out": None, "--arc": 0.008 * 3 * math.pi / 4}
    for key in options:
        if key in args:
            k = args.index(key)
            if k + 1 >= len(args):
                sys.exit(f"{key} needs a value")
            options[key] = args[k + 1]
            del args[k:k + 2]
    out = Path(options["--out"]) if options["--out"] else None
    if out:
        out.mkdir(parents=True, exist_ok=True)
    arc_length = float(options["--arc"])
    runs = [Path(a) for a in args]
    if not runs:
        sys.exit(__doc__)
    fig, (ax_n, ax_f, ax_t) = plt.subplots(3, 1, figsize=(7, 10), sharex=True)
    styles = ["-", "--", "-.", ":"]
    print("| run | closure | needle force [N] | tension at the swage [N] | at the free end [N] | "
          "change [N] | Σ friction [N] | holes' normal force [N] | holes' friction [N] | "
          "sections' tension, from the swage [N] |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for run in runs:
        label, s, closure = load(run)
        colour = None
        for k, i in enumerate(s["normal"]):
            style = styles[k % len(styles)]
            line = ax_n.plot(s["time"], s["normal"][i], ls=style, color=colour,
                             label=f"{label}, hole {i}")[0]
            colour = line.get_color()
            ax_f.plot(s["time"], s["friction"][i], ls=style, color=colour)
        ax_t.plot(s["time"], s["free"], color=colour, label=f"{label}, free end")
        ax_t.plot(s["time"], s["swage"], color=colour, ls="--", label=f"{label}, swage")
        ax_t.plot(s["time"], s["needle"], color=colour, ls=":", label=f"{label}, needle |F|")
        if closure is not None:
            for ax in (ax_n, ax_f, ax_t):
                ax.axvline(closure, color=colour, lw=0.8, alpha=0.6)
            print(balance_row(label, s, closure, section_tensions(run, s, closure, arc_length)))
        else:
            print(f"| {label} | not closed | | | | | | | | |")
    ax_n.set_ylabel("hole's normal force [N]")
    ax_f.set_ylabel("hole's friction on the tissue [N]")
    ax_t.set_ylabel("tension, needle force [N]")
    ax_t.set_xlabel("time [s] (vertical lines: closure)")
    for ax in (ax_n, ax_f, ax_t):
        ax.grid(alpha=0.3)
    ax_n.legend(fontsize="x-small", ncol=2)
    ax_t.legend(fontsize="x-small", ncol=2)
    save(fig, out or runs[0], "pierce_loads")


if __name__ == "__main__":
    main()
