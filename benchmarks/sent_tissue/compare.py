#!/usr/bin/python3
"""Single-edge-notched tension torn by the finite-strain tissue's phase field against
linear elastic fracture mechanics (reference.json: formula, sources, the issue's 5 %).

  /usr/bin/python3 benchmarks/sent_tissue/compare.py OUTPUT --run build/suturesim
  /usr/bin/python3 benchmarks/sent_tissue/compare.py OUTPUT     # OUTPUT/sent_tissue there

The scene pulls by a traction that rises linearly in time, so the run ends (exit 3) when
the crack runs and no equilibrium is left: the critical traction lies between the last
accepted step's traction and the failed attempt's, read from summary.json's error line
("Newton failed at step N (t = T s) ...; last converged state t = T0 s"). The script
checks that the last accepted state is in equilibrium with the traction (the ligament's
reaction in forces.csv, rising linearly in time), that its crack has not run (the nodes with d >= 0.95 in the
kept VTU) and that the run stopped because the tear did not settle; it recomputes LEFM
from parameters.prm and the mesh (W, a, h read off the VTU's reference points), prints
the table with the elastic crack mouth's opening at the first step against Tada's
(and checks it), draws OUTPUT/sent_tissue.png/.pdf (traction against the crack mouth's opening; the damage
along the ligament at each output) and exits 1 outside the tolerance.
"""
import re
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent.parent / "postprocess"))
import benchlib  # noqa: E402
import vtu  # noqa: E402


def columns(path):
    """A CSV file with a header row as {column name: values}."""
    names = open(path).readline().strip().split(",")
    rows = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {name: rows[:, i] for i, name in enumerate(names)}


def geometry(points, damage, a):
    """W, the cell size h on the ligament (the median node spacing along y = 0 beyond a)
    and the crack's tip (the largest x with d >= 0.95 on y = 0) of reference points."""
    on_path = np.abs(points[:, 1]) < 1e-12
    x = np.unique(np.round(points[on_path, 0], 12))
    h = float(np.median(np.diff(x[x >= a - 1e-12])))
    torn = on_path & (damage >= 0.95)
    return float(points[:, 0].max()), h, float(points[torn, 0].max()) if torn.any() else 0.0


def main():
    args = benchlib.arguments(__doc__).parse_args()
    ref = benchlib.reference(__file__)
    run = Path(args.output) / "sent_tissue"
    if args.run:
        benchlib.run(args.run, benchlib.folder_of(__file__) / ref["scene"], run, expected_exit=3)
    summary = benchlib.summary(run)
    prm = benchlib.parameters(run)
    failures = []
    stop = re.search(r"\(t = ([-+.\deE]+) s\) after (\d+) step halvings: (.*); last converged state t = ([-+.\deE]+) s",
                     summary.get("error", ""))
    if summary.get("status") != "failed" or not stop:
        sys.exit(f"sent_tissue: the run did not stop at a failed step (status {summary.get('status')!r}); "
                 "raise End time or the traction's rate")
    t_failed, halvings, why, t_last = float(stop.group(1)), int(stop.group(2)), stop.group(3), float(stop.group(4))

    # the last accepted state: kept on disk by the run, the crack still at the notch
    corners = dict(re.findall(r"(from|to):\s*([^;]+)", prm["Tissue/Phase field/Initial crack"]))
    a = float(corners["to"].split(",")[0])
    kept, path = vtu.series(run / "tissue.pvd")[-1]
    points, _, _, arrays = vtu.read(path)
    W, h, tip = geometry(points, arrays["damage"].reshape(-1), a)
    thickness = float(points[:, 2].max())
    # the error line gives its times to six significant digits (a step halved six times
    # may be shorter than that): equal to within that
    printed = 1e-6 * t_last
    if abs(kept - t_last) > printed:
        failures.append(f"the last VTU is at t = {kept:g} s, not the last accepted state's {t_last:g} s")
    growth = tip - a
    if growth > ref["acceptance"]["stable_growth"]:
        failures.append(f"the crack had grown {1e6 * growth:.0f} um before the failed step: not the onset")
    if "did not settle" not in why:
        failures.append(f"the failed step's reason is not the tear running: {why}")

    # the traction the top carries, from the supports (the ligament's y reaction): a
    # traction rising linearly from zero, so the failed step's is the last one's scaled
    forces = columns(run / "forces.csv")
    if "ligament_reaction_y [N]" not in forces:
        sys.exit("sent_tissue: forces.csv has no column 'ligament_reaction_y [N]'")
    traction = -forces["ligament_reaction_y [N]"] / (W * thickness)
    time = forces["time [s]"]
    if len(time) < 2:
        sys.exit("sent_tissue: forces.csv has no accepted step after t = 0")
    rate = traction[-1] / time[-1]
    if abs(time[-1] - t_last) > printed or np.abs(traction[1:] - rate * time[1:]).max() > 1e-6 * traction[-1]:
        failures.append("the ligament's reaction is not a traction rising linearly in time up to the last accepted "
                        "step")

    mu = float(prm["Tissue/Material/neo-Hookean/Shear modulus"])
    nu = float(prm["Tissue/Material/Poisson ratio"])
    gc = float(prm["Tissue/Phase field/Fracture toughness"])
    ell = float(prm["Tissue/Phase field/Length"])
    E = 2 * mu * (1 + nu)

    # the elastic opening of the crack's mouth at the first load step (the linear limit):
    # twice the upper half's u_y at the notch's mouth against Tada's 4 sigma a V1(a/W)/E'
    first = 1
    opening = 2 * forces["mouth_displacement_y [m]"][first]
    opening_tada = benchlib.sent_mouth_opening(E, nu, traction[first], a, W)
    opening_error = opening / opening_tada - 1
    g_eff = benchlib.at1_effective_toughness(gc, ell, h)
    reference = benchlib.sent_critical_traction(E, nu, gc, ell, h, a, W)
    lo, hi = rate * time[-1], rate * max(t_failed, time[-1])
    critical = (lo + hi) / 2
    error = critical / reference - 1
    tolerance = ref["acceptance"]["relative_error"]
    benchlib.table(["quantity", "suturesim", "LEFM", "difference", "tolerance (source)"], [
        ["critical traction [Pa]", f"{critical:.6g} ({lo:.6g} - {hi:.6g})", f"{reference:.6g}",
         f"{100 * error:+.2f} %", f"{100 * tolerance:g} % ({ref['acceptance']['source']})"],
        [f"mouth opening at {traction[first]:.4g} Pa [um]", f"{1e6 * opening:.6g}", f"{1e6 * opening_tada:.6g}",
         f"{100 * opening_error:+.2f} %",
         f"{100 * ref['acceptance']['mouth_opening']:g} % ({ref['acceptance']['mouth_opening_source']})"],
    ])
    print(f"a = {1e3 * a:g} mm, W = {1e3 * W:g} mm, a/l = {a / ell:g}, h = {1e6 * h:.2f} um, E = {E:.6g} Pa, "
          f"G_eff = {g_eff:.6g} J/m^2, F(a/W) = {benchlib.sent_shape_factor(a / W):.6f}, "
          f"sigma_c/E = {reference / E:.4f}; "
          f"crack growth before the failed step {1e6 * growth:.0f} um; {halvings} halvings")
    if abs(error) > tolerance:
        failures.append(f"critical traction {100 * error:+.2f} % from LEFM, beyond {100 * tolerance:g} %")
    if abs(opening_error) > ref["acceptance"]["mouth_opening"]:
        failures.append(f"the elastic mouth opening is {100 * opening_error:+.2f} % from Tada's, beyond "
                        f"{100 * ref['acceptance']['mouth_opening']:g} %")
    if not args.no_figure:
        figure(run, forces, rate, a, reference, opening_tada / traction[first], stem=Path(args.output) / "sent_tissue")
    benchlib.verdict(failures)


def figure(run, forces, rate, a, reference, compliance, stem):
    plt = benchlib.pyplot()
    fig, (left, right) = plt.subplots(1, 2, figsize=(8, 3.2))
    left.plot(2e6 * forces["mouth_displacement_y [m]"], 1e-3 * rate * forces["time [s]"], "o-", ms=3)
    left.plot([0, 1e6 * compliance * reference], [0, 1e-3 * reference], "k--", lw=1, label="elastic opening (Tada)")
    left.axhline(1e-3 * reference, color="k", ls=":", lw=1, label="critical traction (LEFM)")
    left.set_xlabel("crack mouth opening [um]")
    left.set_ylabel("traction [kPa]")
    left.legend(fontsize=7)
    outputs = vtu.series(run / "tissue.pvd")
    for k, (time, path) in enumerate(outputs):
        points, _, _, arrays = vtu.read(path)
        ligament = (np.abs(points[:, 1]) < 1e-12) & (points[:, 2] < 1e-12) & (points[:, 0] > a - 3e-4)
        x, first = np.unique(np.round(points[ligament, 0], 9), return_index=True)
        right.plot(1e6 * (x - a), arrays["damage"].reshape(-1)[ligament][first], "-", lw=1,
                   color=plt.cm.viridis(k / max(1, len(outputs) - 1)), label=f"{rate * time:.4g} Pa")
    right.set_xlim(-300, 600)
    right.set_xlabel("along the ligament from the notch's tip [um]")
    right.set_ylabel("damage d")
    right.legend(fontsize=6, title="traction", title_fontsize=6)
    benchlib.save_figure(fig, stem)


if __name__ == "__main__":
    main()
