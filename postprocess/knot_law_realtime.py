#!/usr/bin/python3
"""A realtime knot pulled tight beside Audoly et al.'s frictionless law F = B/(2R^2)
(PRL 99, 164301, 2007; docs/knots.md): for each state suture.pvd lists, the end force
the run recorded then (forces.csv, suture_end_force_*) against the law's force at the
knot's radius of curvature R, with B the realtime rope's own bending stiffness.

Usage: /usr/bin/python3 postprocess/knot_law_realtime.py RUN --bending C

C is the rope's curvature stiffness c (N/m) of Realtime/xpbd-rod/Bending stiffness (the
energy c/2 |x_{i-1} - 2 x_i + x_{i+1}|^2), so that B = c l^3 with l the rope's link
length (its mean in the first state). R is 1/max kappa over the knot's nodes: those with
a node more than three links along the rope within four diameters (the strands that
meet); kappa the discrete curvature 2 tan(phi/2)/l at a node. Writes RUN/knot_law.csv
(time, R, F, the law's F, their ratio) and prints it; states without such nodes (no knot
yet) are left out.
"""
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import vtu  # noqa: E402


def nodes(path):
    points = vtu.read(path)[0]
    return np.vstack([points[::2], points[-1]])  # one cell per link, its two points per cell


def knot_radius(x, link, diameter):
    """1/max kappa over the nodes where strands meet (0: none)."""
    gaps = np.linalg.norm(x[:, None, :] - x[None, :, :], axis=2)
    i, j = np.indices(gaps.shape)
    meeting = np.any((gaps < 4 * diameter) & (np.abs(i - j) > 3), axis=1)[1:-1]
    a, b = x[1:-1] - x[:-2], x[2:] - x[1:-1]
    a /= np.linalg.norm(a, axis=1)[:, None]
    b /= np.linalg.norm(b, axis=1)[:, None]
    kappa = 2 * np.linalg.norm(np.cross(a, b), axis=1) / (1 + np.sum(a * b, axis=1)) / link
    return 1 / kappa[meeting].max() if meeting.any() and kappa[meeting].max() > 0 else 0.0


def main(argv):
    if len(argv) != 3 or argv[1] != "--bending":
        sys.exit(__doc__)
    run, c = Path(argv[0]), float(argv[2])
    summary = json.load(open(run / "summary.json"))
    diameter = 2 * summary["suture"]["radius"]
    forces = np.genfromtxt(run / "forces.csv", delimiter=",", names=True)
    names = forces.dtype.names
    end = [n for n in names if n.startswith("suture_end_force")]
    if len(end) != 3:
        sys.exit(f"{run}/forces.csv has no suture_end_force columns (a realtime suture run?)")
    force = np.sqrt(sum(forces[n] ** 2 for n in end))
    states = vtu.series(str(run / "suture.pvd"))
    first = nodes(states[0][1])
    link = np.linalg.norm(np.diff(first, axis=0), axis=1).mean()
    B = c * link ** 3
    rows = []
    for t, path in states:
        R = knot_radius(nodes(path), link, diameter)
        if R == 0:
            continue
        F = force[np.argmin(np.abs(forces[names[0]] - t))]
        law = B / (2 * R * R)
        rows.append((t, R, F, law, F / law))
    header = "time [s],R [m],F [N],law B/(2R^2) [N],F/law [1]"
    np.savetxt(run / "knot_law.csv", np.array(rows).reshape(-1, 5), delimiter=",", header=header, comments="")
    print(f"B = c l^3 = {B:.4g} N m^2 (c = {c:g} N/m, l = {link * 1e3:.4g} mm)")
    print("t [s]  R [mm]  F [N]  law [N]  F/law")
    for t, R, F, law, ratio in rows:
        print(f"{t:.2f}  {R * 1e3:.3f}  {F:.4g}  {law:.4g}  {ratio:.3g}")
    print(f"wrote {run / 'knot_law.csv'}")


if __name__ == "__main__":
    main(sys.argv[1:])
