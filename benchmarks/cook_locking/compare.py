#!/usr/bin/python3
"""Volumetric locking on Cook's membrane at nu = 0.4999 (reference.json: elements, meshes,
the converged tip displacement and its source, the rate checks).

  /usr/bin/python3 benchmarks/cook_locking/compare.py OUTPUT --run build/suturesim
  /usr/bin/python3 benchmarks/cook_locking/compare.py OUTPUT      # runs already there

Runs (or reads) OUTPUT/<element>_n<n> for every element and mesh of reference.json, or
of --meshes for every element (checked only on reference.json's meshes); prints per element n, tip u_y, the error against the
converged value and the observed rate (as tests/unit/cook_locking_test.cc, which makes
the same checks on the same meshes); draws OUTPUT/cook_locking.png/.pdf (error against n)
and exits 1 when a check fails.
"""
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import benchlib  # noqa: E402


def main():
    parser = benchlib.arguments(__doc__)
    parser.add_argument("--meshes", type=lambda s: [int(n) for n in s.split(",")],
                        help="elements per edge for every element, e.g. 2,4,8,16,32 (default: reference.json)")
    args = parser.parse_args()
    ref = benchlib.reference(__file__)
    here = benchlib.folder_of(__file__)
    converged = ref["converged_tip_displacement_y"]
    u_ref, checks = converged["value"], ref["checks"]
    out = Path(args.output)

    results, failures, rows = {}, [], []
    for element in ref["elements"]:
        meshes = args.meshes or element["meshes"]
        previous = None
        for n in meshes:
            run = out / f"{element['name']}_n{n}"
            if args.run:
                benchlib.run(args.run, here / ref["scene"], run, ref["settings"] + [
                    f"Tissue/Element degree={element['degree']}", f"Tissue/Formulation={element['formulation']}",
                    f"Mesh/Elements per edge={n}"])
            u = benchlib.summary(run)["metrics"]["tip_displacement_y"]
            error = abs(u - u_ref)
            rate = benchlib.rate(previous[1], error, n / previous[0]) if previous else float("nan")
            results.setdefault(element["name"], []).append((n, error))
            rows.append([element["name"], n, f"{1e3 * u:.5f}", f"{1e3 * error:.5f}", f"{error / u_ref:.3e}",
                         "-" if math.isnan(rate) else f"{rate:.2f}"])
            checked = n in element["meshes"]  # --meshes beyond the test's are shown, not checked
            if checked and element["expect"] == "converges" and n >= element["rate_from_n"] and rate < checks["mixed_rate_min"]:
                failures.append(f"{element['name']} onto n = {n}: rate {rate:.2f} < {checks['mixed_rate_min']}")
            if checked and element["expect"] == "locks":
                if error <= checks["locked_error_fraction"] * u_ref:
                    failures.append(f"Q1 n = {n}: error {error / u_ref:.3f} u_ref, not locked")
                if not math.isnan(rate) and rate >= checks["locked_rate_max"]:
                    failures.append(f"Q1 onto n = {n}: rate {rate:.2f}, not locked")
            previous = (n, error)

    print(f"Cook's membrane, nu = 0.4999; u_ref = {1e3 * u_ref:.4f} mm ({converged['method']})")
    benchlib.table(["element", "n", "tip u_y [mm]", "error [mm]", "error / u_ref", "rate"], rows)
    print(f"checks (on the meshes of reference.json; why: its 'checks'): mixed rate >= {checks['mixed_rate_min']}; "
          f"Q1 error > {checks['locked_error_fraction']} u_ref and rate < {checks['locked_rate_max']}")
    if not args.no_figure:
        figure(results, out / "cook_locking")
    benchlib.verdict(failures)


def figure(results, stem):
    plt = benchlib.pyplot()
    fig, ax = plt.subplots(figsize=(4.8, 3.6))
    for name, marker in (("Q1", "s"), ("Q1-P0", "o"), ("Q2", "^"), ("Q2-P1", "D")):
        if name in results:
            n, e = zip(*results[name])
            ax.loglog(n, [1e3 * x for x in e], marker + "-", label=name)
    n0 = 4
    for p, style in ((1.0, ":"), (2.0, "--")):
        ax.loglog([n0, 16], [0.3 * (n0 / m) ** p for m in (n0, 16)], "k" + style, lw=0.8, label=f"rate {p:g}")
    ax.set_xscale("log", base=2)
    ax.set_xlabel("elements per edge n")
    ax.set_ylabel("|tip $u_y$ - $u_{ref}$| [mm]")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3, which="both")
    benchlib.save_figure(fig, stem)


if __name__ == "__main__":
    main()
