#!/usr/bin/python3
"""Picture of a knot a run tied: the suture's last state seen along the planner's
projection normal, coloured by height; below it the knot zoomed, its crossings numbered
as in the raw Gauss code (metrics.knot.raw_gauss_code).

Usage: /usr/bin/python3 postprocess/plot_knot.py OUTPUT_DIR [OUTPUT_DIR ...] [--out FIGURE]

Two panels per run (its summary.json needs metrics.knot: a scene with a Knot subsection),
the whole rope titled with the knot, the Gauss code after the Reidemeister reductions and whether it is
the code the plan ties; the moving end is marked with a star. FIGURE (default
OUTPUT_DIR/knot.png, and .pdf beside it) holds them side by side.
"""
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import vtu  # noqa: E402
from figure import save_png_and_pdf  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def last_state(run):
    """The suture's nodes in the last state the run wrote (suture.pvd's last file)."""
    files = vtu.series(str(run / "suture.pvd"))
    if not files:
        sys.exit(f"{run}/suture.pvd lists no state")
    points = vtu.read(files[-1][1])[0]
    # one cell per segment, its two points written per cell
    return np.vstack([points[::2], points[-1]])


def frame(normal):
    """In-plane axes u, v of the plane with unit normal n (as knot::Projection)."""
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    least = int(np.argmin(np.abs(n)))
    u = np.eye(3)[least] - n[least] * n
    u /= np.linalg.norm(u)
    return n, u, np.cross(n, u)


def about(summary):
    """The scene and its path: for the realtime one its suture model and self-collision."""
    rt = summary.get("realtime") or {}
    if rt:
        model = f" ({rt['suture_model']}, {rt['self_collision']})"
    elif summary.get("model") == "accurate":
        model = " (accurate: Cosserat rod)"
    else:
        model = ""
    return f"{summary.get('scene', '')}{model}"


def status(knot):
    """Whether the code is the planned one; a knot specimen's (reads_planned_code) may
    also be tied as its determinant tells with a diagram the reductions do not bring
    down to the planned one."""
    if knot.get("reads_planned_code", knot["tied"]):
        return "as planned"
    if knot["tied"]:
        return f"determinant {knot['determinant']}: the planned knot"
    return "not the planned " + knot["planned_gauss_code"]


def draw(ax, p, h, at, knot, zoom, heading):
    """The projected rope p coloured by height h; zoomed on its crossings at (projected,
    in the order of their labels), numbered."""
    ax.plot(p[:, 0], p[:, 1], color="0.6", lw=0.8, zorder=1)
    dots = ax.scatter(p[:, 0], p[:, 1], c=h, s=9 if not zoom else 16, cmap="coolwarm", zorder=2,
                      vmin=-np.abs(h).max(), vmax=np.abs(h).max())
    both = knot.get("moves_first_end", False)  # the planner moved each end in turn
    ax.plot(*p[0], "ks", ms=7, label="first end (moved too)" if both else "held end")
    ax.plot(*p[-1], "g*", ms=12, label="last end" if both else "moving end")
    ax.set_aspect("equal")
    ax.set_xlabel("u [mm]")
    ax.set_ylabel("v [mm]")
    if zoom and len(at):
        lo, hi = at.min(axis=0) - 3, at.max(axis=0) + 3
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        for k, point in enumerate(at, start=1):
            ax.annotate(str(k), point, xytext=(4, 4), textcoords="offset points", fontsize=9,
                        fontweight="bold", zorder=3)
        ax.set_title("the knot, crossings numbered as in the raw Gauss code", fontsize=9)
    else:
        writhe = f", writhe {knot['writhe']}" if "writhe" in knot else ""
        ax.set_title(f"{heading}\n{knot['knot']}: {knot['crossings']} crossings{writhe}\n"
                     f"{knot['gauss_code'] or '(none)'} ({status(knot)})", fontsize=9)
        ax.legend(fontsize=8, loc="best")
    return dots


def main(argv):
    out = None
    if "--out" in argv:
        i = argv.index("--out")
        out = Path(argv[i + 1])
        argv = argv[:i] + argv[i + 2:]
    runs = [Path(a) for a in argv]
    if not runs:
        sys.exit(__doc__)
    fig, axes = plt.subplots(2, len(runs), figsize=(5.5 * len(runs), 8), squeeze=False)
    for column, run in enumerate(runs):
        summary = json.load(open(run / "summary.json"))
        knot = summary["metrics"].get("knot")
        if knot is None:
            sys.exit(f"{run}/summary.json has no metrics.knot (the scene ties no knot)")
        n, u, v = frame(knot["projection_normal"])
        x = last_state(run)
        p, h = np.column_stack([x @ u, x @ v]) * 1e3, x @ n * 1e3
        # the crossings as the run found them (knot::KnotDiagram), labelled as its code
        c = np.asarray(knot.get("crossing_points", []), float).reshape(-1, 3)
        at = np.column_stack([c @ u, c @ v]) * 1e3
        for row in (0, 1):
            heading = about(summary) + ("" if run.name == summary.get("scene") else f" ({run.name})")
            dots = draw(axes[row][column], p, h, at, knot, zoom=row == 1, heading=heading)
            fig.colorbar(dots, ax=axes[row][column], label="height along the normal [mm]", shrink=0.8)
    save_png_and_pdf(fig, out or runs[0] / "knot.png")


if __name__ == "__main__":
    main(sys.argv[1:])
