#!/usr/bin/python3
"""A node's own 3x3 stiffness block from the cells around it alone, by central
differences of their energy with every other node held, as the damage there rises:
an estimate beside the assembled block postprocess/tangent_eigenvalues.py reads.
docs/tearing.md ("Why the coupled solve fails there"):

  /usr/bin/python3 postprocess/node_block.py OUTPUT/tissue_00061.vtu --node=-3.665,0,2 \\
      --mu 2.22e6 --nu 0.45 --residual 1e-3

The cells' energy is the mean-dilatation Q1-P0 form's: the isochoric neo-Hookean
mu/2 (J^(-2/3) I1 - 3) at 2x2x2 Gauss points times g(d) = (1 - d)^2 + k (d interpolated),
plus kappa G(J~) V with Simo & Taylor's G = (J^2 - 1 - 2 ln J)/4 of the cell's volume
ratio J~, times the cell's mean g when J~ > 1. An estimate: the model's own mixed
three-field cell differs in detail (at the stitch's hole it gives 1145 N/m where the
assembled block is 1302 N/m). Eigenvalues in N/m.
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vtu  # noqa: E402

CORNERS = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
G = (1 - 1 / np.sqrt(3)) / 2
GAUSS = [np.array([a, b, c]) for a in (G, 1 - G) for b in (G, 1 - G) for c in (G, 1 - G)]


def shape(xi):
    """Q1's values and reference gradients at xi, VTK's corner order."""
    factors = np.where(CORNERS == 1, xi, 1 - xi)
    gradients = np.empty((8, 3))
    for i in range(3):
        others = [j for j in range(3) if j != i]
        gradients[:, i] = np.where(CORNERS[:, i] == 1, 1.0, -1.0) * factors[:, others].prod(axis=1)
    return factors.prod(axis=1), gradients


def cell_energy(X, x, d, mu, kappa, residual):
    isochoric, V, v, weighted = 0.0, 0.0, 0.0, 0.0
    for xi in GAUSS:
        N, dN = shape(xi)
        JX = X.T @ dN
        w = np.linalg.det(JX) / 8
        F = x.T @ (dN @ np.linalg.inv(JX))
        J = np.linalg.det(F)
        if J <= 0:
            return np.inf
        g = (1 - N @ d) ** 2 + residual
        isochoric += g * mu / 2 * (J ** (-2 / 3) * np.trace(F.T @ F) - 3) * w
        V, v, weighted = V + w, v + J * w, weighted + g * w
    Jt = v / V
    return isochoric + (weighted / V if Jt > 1 else 1.0) * kappa * (Jt * Jt - 1 - 2 * np.log(Jt)) / 4 * V


def block(cells, X, x, d, node, mu, kappa, residual, h=2e-8):
    """Eigenvalues of the energy's 3x3 Hessian in the position of point group @p node."""
    def total(y):
        moved = x.copy()
        moved[node] = y
        return sum(cell_energy(X[c], moved[c], d[c], mu, kappa, residual) for c in cells)
    y0, H = x[node][0].copy(), np.zeros((3, 3))
    for a in range(3):
        for b in range(3):
            ea, eb = h * np.eye(3)[a], h * np.eye(3)[b]
            H[a, b] = (total(y0 + ea + eb) - total(y0 + ea - eb) - total(y0 - ea + eb)
                       + total(y0 - ea - eb)) / (4 * h * h)
    return np.linalg.eigvalsh((H + H.T) / 2)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("vtu", help="a tissue VTU of a run with Tissue/Phase field")
    parser.add_argument("--node", required=True, help="x,y,z (mm, reference): the node nearest it")
    parser.add_argument("--mu", type=float, required=True, help="shear modulus (Pa)")
    parser.add_argument("--nu", type=float, required=True, help="Poisson's ratio")
    parser.add_argument("--residual", type=float, required=True, help="the phase field's residual stiffness k")
    args = parser.parse_args()
    X, connectivity, _, arrays = vtu.read(args.vtu)
    u, d = arrays["displacement"].astype(float), arrays["damage"].reshape(-1).astype(float)
    cells = np.asarray(connectivity).reshape(-1, 8)
    at = 1e-3 * np.array([float(v) for v in args.node.split(",")])
    nearest = X[np.argmin(np.linalg.norm(X - at, axis=1))]
    node = np.linalg.norm(X - nearest, axis=1) < 1e-9
    around = [c for c in cells if node[c].any()]
    kappa = 2 * args.mu * (1 + args.nu) / (3 * (1 - 2 * args.nu))
    x = X + u
    print("the node at (%s) mm, %d cells, d there %.3f" % (", ".join("%.3f" % (1e3 * v) for v in nearest),
                                                            len(around), d[node].max()))
    members = np.unique(np.concatenate(around))
    rows = [("as written", d)]
    for scale in (1.5, 2, 3):
        rows.append(("d x %g" % scale, np.where(np.isin(np.arange(len(d)), members), np.minimum(1, d * scale), d)))
    for floor in (0.6, 0.8, 0.9, 0.95):
        rows.append(("d >= %g on the cells" % floor, np.where(np.isin(np.arange(len(d)), members),
                                                              np.maximum(d, floor), d)))
    for label, damage in rows:
        values = block(around, X, x, damage, node, args.mu, kappa, args.residual)
        print("%-22s %s" % (label, " ".join("%.4g" % v for v in values)), flush=True)


if __name__ == "__main__":
    main()
