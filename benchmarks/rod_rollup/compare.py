#!/usr/bin/python3
"""Roll-up of a clamped rod by an end moment against the closed form of the discrete rod
(reference.json: formula, source, tolerances).

  /usr/bin/python3 benchmarks/rod_rollup/compare.py OUTPUT --run build/suturesim
  /usr/bin/python3 benchmarks/rod_rollup/compare.py OUTPUT     # OUTPUT/rod_rollup there

Reads the run's summary.json (tip, double precision), parameters.prm (N, L, r, E, M) and
the last suture_*.vtu (every node, 32-bit floats); prints the tip and the largest node
error against the closed form; draws OUTPUT/rod_rollup.png/.pdf (the rod after each
load step); exits 1 when the issue-3 acceptance, the regression tolerance or the node
tolerance is exceeded.
"""
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent.parent / "postprocess"))
import benchlib  # noqa: E402
import vtu  # noqa: E402


def closed_form(N, L, M, EI):
    """Nodes x_k = L0 sum_{j<k} (cos((j + 1/2) phi), sin((j + 1/2) phi)), phi = M L0 / EI."""
    L0 = L / N
    phi = M * L0 / EI
    steps = L0 * np.array([[math.cos((j + 0.5) * phi), math.sin((j + 0.5) * phi), 0.0] for j in range(N)])
    return np.vstack([np.zeros(3), np.cumsum(steps, axis=0)])


def main():
    args = benchlib.arguments(__doc__).parse_args()
    ref = benchlib.reference(__file__)
    run = Path(args.output) / "rod_rollup"
    if args.run:
        benchlib.run(args.run, benchlib.folder_of(__file__) / ref["scene"], run)
    prm = benchlib.parameters(run)
    N = int(prm["Suture/Elements"])
    L = float(prm["Suture/Straight/Length"])
    r = float(prm["Suture/Cross section/Radius"])
    E = float(prm["Suture/Cross section/Young's modulus"])
    M = float(prm["Suture/Loads/End moment"].split(",")[2])
    EI = E * math.pi * r ** 4 / 4
    exact = closed_form(N, L, M, EI)

    tip = np.array(benchlib.summary(run)["metrics"]["tip_position"])
    frames = vtu.series(str(run / "suture.pvd"))
    points = vtu.read(frames[-1][1])[0]
    nodes = np.vstack([points[0::2], points[-1]])  # each segment writes its own two points
    node_error = np.max(np.linalg.norm(nodes - exact, axis=1))
    tip_error = np.linalg.norm(tip - exact[-1])

    acceptance = ref["acceptance"]["tip_distance_from_root_m"]
    regression = ref["regression"]["tip_minus_closed_form_m"]
    node_tolerance = ref["nodes"]["tolerance_m"]
    print(f"roll-up: N = {N}, L = {L} m, EI = {EI:.6e} N m^2, M = {M} N m (2 pi EI / L = {2 * math.pi * EI / L:.9e})")
    benchlib.table(["quantity", "suturesim", "reference", "difference", "tolerance (source)"], [
        ["tip distance from the root [m]", f"{np.linalg.norm(tip):.4e}", "0 (M = 2 pi EI/L)",
         f"{np.linalg.norm(tip):.2e}", f"{acceptance:g} ({ref['acceptance']['source']})"],
        ["tip [m]", f"({tip[0]:.6e}, {tip[1]:.1e})", f"({exact[-1][0]:.6e}, {exact[-1][1]:.1e}) closed form",
         f"{tip_error:.2e}", f"{regression:g} (regression, measured spread {ref['regression']['measured_spread_m']:g})"],
        ["largest node error [m] (last .vtu)", "", "closed form", f"{node_error:.2e}", f"{node_tolerance:g} (32-bit output)"],
    ])
    failures = []
    if np.linalg.norm(tip) > acceptance:
        failures.append(f"tip {np.linalg.norm(tip):.3e} m from the root > {acceptance:g} m")
    if tip_error > regression:
        failures.append(f"tip {tip_error:.3e} m from the closed form > {regression:g} m")
    if node_error > node_tolerance:
        failures.append(f"a node {node_error:.3e} m from the closed form > {node_tolerance:g} m")
    if not args.no_figure:
        figure(frames, L, Path(args.output) / "rod_rollup")
    benchlib.verdict(failures)


def figure(frames, L, stem):
    plt = benchlib.pyplot()
    fig, ax = plt.subplots(figsize=(4.5, 3.5))
    for t, path in frames:
        p = vtu.read(path)[0]
        ax.plot(1e3 * p[:, 0], 1e3 * p[:, 1], "-", lw=1, color=plt.cm.viridis(t), label=f"{t:.1f}" if t in (0, 1) else None)
    R = L / (2 * math.pi)
    a = np.linspace(0, 2 * math.pi, 200)
    ax.plot(1e3 * R * np.sin(a), 1e3 * R * (1 - np.cos(a)), "k:", lw=1, label="circle L/2$\\pi$")
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.legend(title="load factor", fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1))
    benchlib.save_figure(fig, stem)


if __name__ == "__main__":
    main()
