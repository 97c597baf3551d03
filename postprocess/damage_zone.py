#!/usr/bin/python3
"""Where the phase field's damage stands in an accurate run's last tissue VTU (or the
one at --time): the largest damage, the largest principal stretch and the extremes of
J with their reference points and the damage there, and the box (reference
configuration) of the nodes with d above --threshold. docs/tearing.md ("What stops it")
describes the stitch's torn hole with it:

  /usr/bin/python3 postprocess/damage_zone.py OUTPUT --threshold=0.2

Lengths in mm; the arrays are the VTU's point arrays damage, J and max_principal_stretch
(a run with Tissue/Phase field).
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
    parser.add_argument("--threshold", type=float, default=0.2, help="d above which a node counts as damaged")
    parser.add_argument("--time", type=float, help="the output at this time (s); default the last")
    args = parser.parse_args()
    pvd = os.path.join(args.run, "tissue.pvd")
    if not os.path.isfile(pvd):
        sys.exit("damage_zone.py: %s has no tissue.pvd (not an accurate run's output folder)" % args.run)
    outputs = vtu.series(pvd)
    if not outputs:
        sys.exit("damage_zone.py: %s has no tissue outputs" % args.run)
    time, path = outputs[-1] if args.time is None else min(outputs, key=lambda o: abs(o[0] - args.time))
    points, _, _, arrays = vtu.read(path)
    missing = [a for a in ("damage", "J", "max_principal_stretch") if a not in arrays]
    if missing:
        sys.exit("damage_zone.py: %s has no %s (written without Tissue/Phase field?)" % (path, ", ".join(missing)))
    d, J, stretch = (arrays[a].reshape(-1) for a in ("damage", "J", "max_principal_stretch"))
    X = 1e3 * points
    print("%s at t = %.6g s" % (os.path.basename(path), time))
    for label, i in (("largest d", np.argmax(d)), ("largest stretch", np.argmax(stretch)),
                     ("largest J", np.argmax(J)), ("smallest J", np.argmin(J))):
        print("  %-16s at (%.3f, %.3f, %.3f) mm: d %.3f, stretch %.3f, J %.3f"
              % (label, *X[i], d[i], stretch[i], J[i]))
    damaged = d > args.threshold
    if not damaged.any():
        print("  no node with d > %g" % args.threshold)
        return
    lo, hi = X[damaged].min(axis=0), X[damaged].max(axis=0)
    print("  %d nodes with d > %g within x %.3f to %.3f, y %.3f to %.3f, z %.3f to %.3f mm"
          % (damaged.sum(), args.threshold, lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]))


if __name__ == "__main__":
    main()
