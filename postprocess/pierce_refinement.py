#!/usr/bin/python3
"""How a stitch's pierce points load the tissue on each mesh of a refinement series
(docs/tearing.md, "Onset under refinement"):

  /usr/bin/python3 postprocess/pierce_refinement.py RUN [RUN ...] --at 4.0 [--radius 0.002]

For each accurate stitch run it prints, at time --at (s; interpolated in forces.csv),
each pierce point's normal force over the pull tension (pierce_<i>_normal_force over
pull_tension), and the material points the needle punctured (the tracts' ends in
summary.json's metrics.tearing). With --radius it also prints, for each tract end on a
wound face, the share of the spread kernel (1 - s^2)^2, s = r/radius, that lies on the
other side of the wound (x of the other sign, above the incision's floor z = 3 mm), over
the first tissue VTU's cells (kernel at the cell centre times the cell's volume): what
Pierce points/Load across the wound = true lets a face point take of the other lip.
Needs Tearing/Criteria in the runs (the tracts).
"""
import argparse
import csv
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vtu  # noqa: E402

FLOOR = 0.003  # m, the incision's floor in meshes/skin_pad_incision.geo


def hexahedron_volumes(P):
    """Volumes of hexahedra (n, 8, 3), deal.II's vertex order, as six tetrahedra."""
    volume = np.zeros(len(P))
    for a, b, c, d in [(0, 1, 3, 7), (0, 1, 5, 7), (0, 4, 5, 7), (0, 2, 3, 7), (0, 2, 6, 7), (0, 4, 6, 7)]:
        volume += np.abs(np.einsum("ij,ij->i", P[:, b] - P[:, a], np.cross(P[:, c] - P[:, a], P[:, d] - P[:, a]))) / 6
    return volume


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--at", type=float, required=True, help="time (s)")
    parser.add_argument("--radius", type=float, help="the spread kernel's radius (m)")
    args = parser.parse_args()
    for run in args.runs:
        with open(os.path.join(run, "forces.csv")) as f:
            rows = list(csv.reader(f))
        header, data = rows[0], np.array([[float(x) for x in r] for r in rows[1:]])
        value = lambda name: np.interp(args.at, data[:, 0], data[:, header.index(name)])  # noqa: E731
        tension = value("pull_tension [N]")
        loads = []
        k = 0
        while "pierce_%d_normal_force [N]" % k in header:
            loads.append(value("pierce_%d_normal_force [N]" % k) / tension)
            k += 1
        print("%s at %g s: pull tension %.3f N; normal force over it: %s" %
              (run, args.at, tension, ", ".join("%.3f" % n for n in loads)))
        tearing = json.load(open(os.path.join(run, "summary.json")))["metrics"]["tearing"]
        tracts = next(iter(tearing["criteria"].values()))["tracts"]
        ends = [np.array(p) for t in tracts for p in (t["entry"], t["exit"])]
        print("  tract ends (mm): " + "; ".join("(%.3f, %.3f, %.3f)" % tuple(1e3 * p) for p in ends))
        if not args.radius:
            continue
        _, path = vtu.series(os.path.join(run, "tissue.pvd"))[0]
        points, connectivity, offsets, _ = vtu.read(path)
        if offsets is None or np.any(np.diff(offsets) != 8):
            sys.exit("pierce_refinement.py: %s: hexahedral cells expected" % path)
        cells = points[connectivity.reshape(-1, 8)]
        centre, volume = cells.mean(axis=1), hexahedron_volumes(cells)
        for X in ends:
            if abs(X[0]) > args.radius:  # not near the wound
                continue
            s = np.linalg.norm(centre - X, axis=1) / args.radius
            w = np.where(s < 1, (1 - s ** 2) ** 2, 0) * volume
            other = (np.sign(centre[:, 0]) != np.sign(X[0])) & (centre[:, 2] > FLOOR)
            print("  face point (%.3f, %.3f, %.3f) mm: %.3f of its kernel on the other lip" %
                  (*(1e3 * X), w[other].sum() / w.sum()))


if __name__ == "__main__":
    main()
