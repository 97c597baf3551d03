#!/usr/bin/env python3
"""A picture of a tissue-and-suture run from its own output (the README's picture of the
stitch): the deformed skin surface around the suture and the suture at a few instants.

  /usr/bin/python3 postprocess/plot_scene.py output/stitch_interrupted [t1 t2 ...]

Without times it draws the end of the needle's turn, the tail's grasp (Suture/Last end),
and the last output. Writes scene.png and scene.pdf into the run's folder. The tissue is
drawn as its boundary triangles within 10 mm of the suture's pierced part, see-through,
so that the thread inside shows; the suture in red. Reads the .pvd/.vtu series with
postprocess/vtu.py (no VTK needed); for anything more, open the .pvd files in ParaView.
"""
import json
import re
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
import vtu  # noqa: E402
from plot_forces import save  # noqa: E402

# faces of a tetrahedron (VTK order of its four vertices)
TET_FACES = ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3))


def boundary_faces(points, connectivity, offsets):
    """Boundary triangles of a tetrahedral mesh written with points per cell: vertices
    merged by position (at t = 0, where coinciding points are one vertex), faces that
    belong to one tetrahedron only. Returns (vertex of each point, triangles as point
    indices)."""
    if np.any(np.diff(np.concatenate(([0], offsets))) != 4):
        sys.exit("plot_scene.py: the tissue must be tetrahedra (realtime output)")
    keys = np.round(points / 1e-9).astype(np.int64)
    _, vertex = np.unique(keys, axis=0, return_inverse=True)
    vertex = vertex.reshape(-1)
    cells = connectivity.reshape(-1, 4)
    faces = np.concatenate([cells[:, f] for f in TET_FACES])
    key = np.sort(vertex[faces], axis=1)
    _, first, count = np.unique(key, axis=0, return_index=True, return_counts=True)
    return vertex, faces[first[count == 1]]


def at(series, t):
    """The file of @p series whose time is nearest @p t."""
    return min(series, key=lambda e: abs(e[0] - t))


def default_times(run, series):
    summary = json.load(open(run / "summary.json"))
    times = []
    turn = summary.get("needle", {}).get("pass", {}).get("t_turn_end")
    if turn is not None:
        times.append(turn)
    grasp = re.search(r"subsection Last end.*?set Grasp time\s*=\s*([0-9.eE+-]+)",
                      open(run / "parameters.prm").read(), re.S)
    if grasp and float(grasp.group(1)) > 0:
        times.append(float(grasp.group(1)))
    times.append(series[-1][0])
    return sorted(set(times))


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    run = Path(sys.argv[1])
    tissue = vtu.series(str(run / "tissue.pvd"))
    suture = vtu.series(str(run / "suture.pvd"))
    times = [float(a) for a in sys.argv[2:]] or default_times(run, tissue)
    points0, connectivity, offsets, _ = vtu.read(tissue[0][1])
    _, triangles = boundary_faces(points0, connectivity, offsets)
    summary = json.load(open(run / "summary.json"))
    # one window for every instant: around the punctures (else the mesh's centre)
    punctures = [e["position"] for e in summary.get("events", []) if e["kind"].startswith("puncture")]
    centre = np.mean(punctures, axis=0) if punctures else points0.mean(axis=0)
    half = 7e-3
    top = points0[:, 2].max()
    mm = 1e3

    fig = plt.figure(figsize=(4.2 * len(times), 4.4))
    for k, t in enumerate(times):
        t_tissue, tissue_file = at(tissue, t)
        _, suture_file = at(suture, t)
        x, _, _, _ = vtu.read(tissue_file)
        s, _, _, _ = vtu.read(suture_file)
        centroids = x[triangles].mean(axis=1)
        keep = np.all(np.abs(centroids[:, :2] - centre[:2]) < half, axis=1)
        # leave out the bottom and the sides below the window
        keep &= centroids[:, 2] > top - 5e-3
        ax = fig.add_subplot(1, len(times), k + 1, projection="3d")
        poly = Poly3DCollection(mm * x[triangles[keep]], facecolor=(0.93, 0.74, 0.66, 0.45),
                                edgecolor=(0.45, 0.35, 0.3, 0.3), linewidths=0.2)
        ax.add_collection3d(poly)
        # the suture within the box (NaN breaks the line where it leaves)
        inside = np.all(np.abs(s[:, :2] - centre[:2]) < half, axis=1) & (np.abs(s[:, 2] - top) < 5e-3)
        shown = np.where(inside[:, None], s, np.nan)
        ax.plot(*(mm * shown).T, color="crimson", lw=1.8)
        for d, axis in enumerate((ax.set_xlim, ax.set_ylim)):
            axis(mm * (centre[d] - half), mm * (centre[d] + half))
        ax.set_zlim(mm * (top - 5e-3), mm * (top + 5e-3))
        ax.set_box_aspect((1, 1, 10e-3 / (2 * half)))
        ax.view_init(elev=24, azim=-70)
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
        ax.set_zlabel("z [mm]")
        ax.set_title(f"t = {t_tissue:.2f} s", fontsize="small")
    fig.suptitle(f"{summary.get('scene', run.name)} ({summary.get('model', '?')})")
    save(fig, run, "scene")


if __name__ == "__main__":
    main()
