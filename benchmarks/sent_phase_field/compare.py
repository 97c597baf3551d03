#!/usr/bin/python3
"""Single-edge-notched tension broken by AT1 phase-field fracture against linear elastic
fracture mechanics (reference.json: formula, sources, the issue's 5 % tolerance).

  /usr/bin/python3 benchmarks/sent_phase_field/compare.py OUTPUT --run build/suturesim
  /usr/bin/python3 benchmarks/sent_phase_field/compare.py OUTPUT     # OUTPUT/sent_phase_field there

Reads the run's summary.json (metrics.fracture: the bracketed critical traction and the
LEFM value the run computed from its own E, nu, G_c, l, h, a and W) and recomputes the
LEFM value here from parameters.prm; prints the table; draws OUTPUT/sent_phase_field.png
/.pdf (traction against the left edge's stretch and the crack tip); exits 1 outside the
tolerance.
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import benchlib  # noqa: E402


def lefm(prm, h):
    """sigma_c = sqrt(E' G_c (1 + 3h/(8l)) / (pi a)) / F(a/W)."""
    get = lambda key: float(prm["Fracture specimen/" + key])  # noqa: E731
    return benchlib.sent_critical_traction(get("Young's modulus"), get("Poisson's ratio"), get("Fracture toughness"),
                                           get("Internal length"), h, get("Notch length"), get("Width"))


def main():
    args = benchlib.arguments(__doc__).parse_args()
    ref = benchlib.reference(__file__)
    run = Path(args.output) / "sent_phase_field"
    if args.run:
        benchlib.run(args.run, benchlib.folder_of(__file__) / ref["scene"], run)
    m = benchlib.summary(run)["metrics"]["fracture"]
    prm = benchlib.parameters(run)
    reference = lefm(prm, m["cell_size_on_path"])
    error = m["critical_traction"] / reference - 1
    tolerance = ref["acceptance"]["relative_error"]
    lo, hi = m["critical_traction_range"]
    benchlib.table(["quantity", "suturesim", "LEFM", "difference", "tolerance (source)"], [
        ["critical traction [Pa]", f"{m['critical_traction']:.6g} ({lo:.6g} - {hi:.6g})", f"{reference:.6g}",
         f"{100 * error:+.2f} %", f"{100 * tolerance:g} % ({ref['acceptance']['source']})"],
    ])
    print(f"a/l = {m['notch_over_length']:g}, h = {m['cell_size_on_path']:.4g} m, G_eff = {m['effective_toughness']:.6g} "
          f"J/m^2, F(a/W) = {m['shape_factor']:.6f}")
    failures = []
    if abs(reference / m["lefm_critical_traction"] - 1) > 1e-9:
        failures.append(f"the run's LEFM value {m['lefm_critical_traction']:.9g} Pa is not this script's {reference:.9g}")
    if abs(error) > tolerance:
        failures.append(f"critical traction {100 * error:+.2f} % from LEFM, beyond {100 * tolerance:g} %")
    if not args.no_figure:
        figure(run, a=float(prm["Fracture specimen/Notch length"]), reference=reference,
               stem=Path(args.output) / "sent_phase_field")
    benchlib.verdict(failures)


def figure(run, a, reference, stem):
    import numpy as np
    rows = np.genfromtxt(run / "forces.csv", delimiter=",", skip_header=1, ndmin=2)
    plt = benchlib.pyplot()
    fig, (left, right) = plt.subplots(1, 2, figsize=(8, 3.2))
    stable = rows[:, 6] > 0
    left.plot(1e6 * rows[stable, 2], 1e-3 * rows[stable, 0], "o-", ms=3, label="stable (crack at the notch)")
    left.plot(1e6 * rows[~stable, 2], 1e-3 * rows[~stable, 0], "x", color="C3", label="the crack runs")
    left.axhline(1e-3 * reference, color="k", ls=":", lw=1, label="LEFM")
    left.set_xlabel("left edge stretch [um]")
    left.set_ylabel("traction [kPa]")
    left.legend(fontsize=7)
    right.plot(1e-3 * rows[:, 0], 1e3 * (rows[:, 1] - a), "o", ms=3)
    right.axvline(1e-3 * reference, color="k", ls=":", lw=1)
    right.set_xlabel("traction [kPa]")
    right.set_ylabel("crack growth beyond the notch [mm]")
    benchlib.save_figure(fig, stem)


if __name__ == "__main__":
    main()
