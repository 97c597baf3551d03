#!/usr/bin/python3
"""Picture of a knot a run tied: the suture's last state seen along the planner's
projection normal, coloured by height, the crossings numbered as in the Gauss code.

Usage: /usr/bin/python3 postprocess/plot_knot.py OUTPUT_DIR [OUTPUT_DIR ...] [--out FIGURE]

One panel per run (its summary.json needs metrics.knot: a scene with a Knot subsection),
titled with the knot, the Gauss code after the Reidemeister reductions and whether it is
the code the plan ties; the moving end is marked with a star. FIGURE (default
OUTPUT_DIR/knot.png, and .pdf beside it) holds them side by side.
"""
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import vtu  # noqa: E402

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


def main(argv):
    out = None
    if "--out" in argv:
        i = argv.index("--out")
        out = Path(argv[i + 1])
        argv = argv[:i] + argv[i + 2:]
    runs = [Path(a) for a in argv]
    if not runs:
        sys.exit(__doc__)
    fig, axes = plt.subplots(1, len(runs), figsize=(5.5 * len(runs), 5), squeeze=False)
    for ax, run in zip(axes[0], runs):
        knot = json.load(open(run / "summary.json"))["metrics"].get("knot")
        if knot is None:
            sys.exit(f"{run}/summary.json has no metrics.knot (the scene ties no knot)")
        n, u, v = frame(knot["projection_normal"])
        x = last_state(run)
        p, h = np.column_stack([x @ u, x @ v]) * 1e3, x @ n * 1e3
        ax.plot(p[:, 0], p[:, 1], color="0.6", lw=0.8, zorder=1)
        dots = ax.scatter(p[:, 0], p[:, 1], c=h, s=9, cmap="coolwarm", zorder=2,
                          vmin=-np.abs(h).max(), vmax=np.abs(h).max())
        ax.plot(*p[0], "ks", ms=7, label="held end")
        ax.plot(*p[-1], "g*", ms=12, label="moving end")
        ax.set_aspect("equal")
        ax.set_xlabel("u [mm]")
        ax.set_ylabel("v [mm]")
        ax.set_title(f"{knot['knot']}: {knot['crossings']} crossings\n{knot['gauss_code'] or '(none)'}"
                     f" ({'as planned' if knot['tied'] else 'not the planned ' + knot['planned_gauss_code']})",
                     fontsize=9)
        ax.legend(fontsize=8, loc="best")
        fig.colorbar(dots, ax=ax, label="height along the normal [mm]", shrink=0.8)
    out = out or runs[0] / "knot.png"
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    fig.savefig(out.with_suffix(".pdf"))
    print(f"wrote {out} and {out.with_suffix('.pdf')}")


if __name__ == "__main__":
    main(sys.argv[1:])
