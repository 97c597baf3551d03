#!/usr/bin/python3
"""Where a tear criterion's cell ratios m/m_c stand at the end of an accurate run: the
largest cells of the last tissue VTU (tear_<criterion>, a cell mean written at the
cell's vertices), and the largest inside each --box. docs/tearing.md ("Onset under
refinement") locates the energy criteria's rising zone mean with it:

  /usr/bin/python3 postprocess/tear_cells.py OUTPUT/cases/reference_L2 fracture-energy \
      --box=-0.001,0.001,-0.015,0.015,0.002,0.004

Boxes are x0,x1,y0,y1,z0,z1 in m, in the reference configuration (the VTU's points).
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vtu  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run", help="an accurate run's output folder (with tissue.pvd)")
    parser.add_argument("criterion", help="a Tearing/Criteria entry, e.g. fracture-energy")
    parser.add_argument("--box", action="append", default=[], help="x0,x1,y0,y1,z0,z1 in m")
    parser.add_argument("--top", type=int, default=3, help="how many of the largest cells to list")
    args = parser.parse_args()
    time, path = vtu.series(os.path.join(args.run, "tissue.pvd"))[-1]
    points, connectivity, offsets, arrays = vtu.read(path)
    name = "tear_" + args.criterion
    if name not in arrays:
        sys.exit("tear_cells.py: %s has no %s (was the criterion in Tearing/Criteria?)" % (path, name))
    if offsets is None or np.any(np.diff(offsets) != 8):
        sys.exit("tear_cells.py: %s: hexahedral cells expected" % path)
    cells = connectivity.reshape(-1, 8)
    ratio = arrays[name][cells].mean(axis=1)
    centre = points[cells].mean(axis=1)
    print("%s at t = %g s: %d cells" % (path, time, len(cells)))
    for k in np.argsort(ratio)[::-1][:args.top]:
        print("  %s %.3f at (%.2f, %.2f, %.2f) mm" % (name, ratio[k], *(1e3 * centre[k])))
    for box in args.box:
        b = [float(v) for v in box.split(",")]
        inside = np.all((centre >= b[0::2]) & (centre <= b[1::2]), axis=1)
        if not inside.any():
            print("  box %s: no cell" % box)
            continue
        k = np.flatnonzero(inside)[np.argmax(ratio[inside])]
        print("  box %s: largest %.3f at (%.2f, %.2f, %.2f) mm" % (box, ratio[k], *(1e3 * centre[k])))


if __name__ == "__main__":
    main()
