#!/usr/bin/python3
"""Compressible Cook's membrane against the deal.II code gallery's published tip
displacements (reference.json: values, source, tolerance).

  /usr/bin/python3 benchmarks/cook_membrane/compare.py OUTPUT --run build/suturesim
  /usr/bin/python3 benchmarks/cook_membrane/compare.py OUTPUT     # runs already there

Runs (or reads) OUTPUT/q<degree>_n<n> for Q1 and Q2 on the meshes of
reference.json["compared"], prints n, published and computed u_y and the relative
error, draws OUTPUT/cook_membrane.png/.pdf, and exits 1 when an error exceeds the
tolerance.
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import benchlib  # noqa: E402


def main():
    parser = benchlib.arguments(__doc__)
    parser.add_argument("--largest", type=int, default=None, help="also compare meshes up to this n")
    args = parser.parse_args()
    ref = benchlib.reference(__file__)
    here = benchlib.folder_of(__file__)
    published = ref["published"]
    meshes = [n for n in published["elements_per_edge"]
              if n in ref["compared"]["elements_per_edge"] or (args.largest and n <= args.largest)]
    tolerance = ref["tolerance"]["relative"]
    out = Path(args.output)

    rows, failures, computed = [], [], {}
    for n in meshes:
        row = [str(n)]
        for degree in (1, 2):
            run = out / f"q{degree}_n{n}"
            if args.run:
                benchlib.run(args.run, here / ref["scene"], run,
                             [f"Mesh/Elements per edge={n}", f"Tissue/Element degree={degree}"])
            prm = benchlib.parameters(run)
            if (prm["Mesh/Elements per edge"], prm["Tissue/Element degree"]) != (str(n), str(degree)):
                sys.exit(f"{run}: not the Q{degree}, n = {n} run")
            u = benchlib.summary(run)["metrics"]["tip_displacement_y"]
            u_pub = published[f"Q{degree}"][published["elements_per_edge"].index(n)]
            error = abs(u - u_pub) / u_pub
            computed[(degree, n)] = u
            row += [f"{1e3 * u_pub:.2f}", f"{1e3 * u:.4f}", f"{100 * error:.3f}"]
            if error > tolerance:
                failures.append(f"Q{degree}, n = {n}: {1e3 * u:.4f} mm against {1e3 * u_pub:.2f} mm "
                                f"({100 * error:.3f} % > {100 * tolerance:.2f} %)")
        rows.append(row)

    print(f"Cook's membrane, tip u_y in mm; tolerance {100 * tolerance:.2f} % ({ref['tolerance']['source']})")
    benchlib.table(["n", "Q1 published", "Q1 suturesim", "Q1 error %",
                    "Q2 published", "Q2 suturesim", "Q2 error %"], rows)
    if not args.no_figure:
        figure(published, meshes, computed, out / "cook_membrane")
    benchlib.verdict(failures)


def figure(published, meshes, computed, stem):
    plt = benchlib.pyplot()
    fig, ax = plt.subplots(figsize=(5, 3.5))
    for degree, colour in ((1, "tab:blue"), (2, "tab:red")):
        ax.plot(published["elements_per_edge"], [1e3 * u for u in published[f"Q{degree}"]], "o",
                mfc="none", color=colour, label=f"Q{degree} published (Pelteret & McBride 2016)")
        ax.plot(meshes, [1e3 * computed[(degree, n)] for n in meshes], "-", color=colour,
                label=f"Q{degree} suturesim")
    ax.set_xscale("log", base=2)
    ax.set_xlabel("elements per edge")
    ax.set_ylabel("tip $u_y$ [mm]")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    benchlib.save_figure(fig, stem)


if __name__ == "__main__":
    main()
