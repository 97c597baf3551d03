#!/usr/bin/python3
"""deal.II step-44's indentation block against step-44's own values (reference.json),
with both updates of the mixed fields.

  /usr/bin/python3 benchmarks/indentation_block/compare.py OUTPUT --run build/suturesim
  /usr/bin/python3 benchmarks/indentation_block/compare.py OUTPUT     # runs already there

Runs (or reads) OUTPUT/newton (p~, J~ as Newton unknowns, the default) and OUTPUT/exact
(recomputed from u at every iterate), prints per load step step-44's and suturesim's top
displacement, their relative difference and the Newton iterations of each (the exact
update, which halves a step, as totals), draws
OUTPUT/indentation_block.png/.pdf, and exits 1 when a displacement differs by more than
the tolerance or the default needs more Newton iterations than step-44 + 1.
"""
import csv
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import benchlib  # noqa: E402

VARIANTS = {"newton": [], "exact": ["Tissue/Mixed update=exact"]}


def top_displacement(run):
    """top_centre_displacement_y after each load step (forces.csv rows after t = 0)."""
    with open(Path(run) / "forces.csv") as f:
        rows = list(csv.DictReader(f))
    key = next(k for k in rows[0] if k.startswith("top_centre_displacement_y"))
    return [float(r[key]) for r in rows[1:]]


def main():
    args = benchlib.arguments(__doc__).parse_args()
    ref = benchlib.reference(__file__)
    here = benchlib.folder_of(__file__)
    step44 = ref["step44"]["direct_static_condensation"]
    tolerance = ref["tolerance"]["relative"]
    extra = ref["tolerance"]["newton_extra_iterations"]
    out = Path(args.output)

    u, its, walls = {}, {}, {}
    for name, settings in VARIANTS.items():
        run = out / name
        if args.run:
            benchlib.run(args.run, here / ref["scene"], run, settings)
        s = benchlib.summary(run)
        u[name] = top_displacement(run)
        its[name] = [step["newton_iterations"] for step in s["steps"][1:]]
        walls[name] = s["wall_time_seconds"]
    if len(u["newton"]) != len(step44["top_displacement_y"]):
        sys.exit(f"{out / 'newton'}: {len(u['newton'])} load steps, step-44 has {len(step44['top_displacement_y'])}")

    rows, failures = [], []
    for k, (t, u44) in enumerate(zip(ref["step44"]["load_steps"], step44["top_displacement_y"])):
        d = abs(u["newton"][k] / u44 - 1)
        digits = -math.log10(d) if d > 0 else 16
        rows.append([f"{t:.1f}", f"{u44:.15e}", f"{u['newton'][k]:.15e}", f"{d:.1e}", f"{digits:.1f}",
                     step44["newton_iterations"][k], its["newton"][k]])
        if d > tolerance:
            failures.append(f"load step {k + 1}: relative difference {d:.1e} > {tolerance:.0e}")
        if its["newton"][k] > step44["newton_iterations"][k] + extra:
            failures.append(f"load step {k + 1}: {its['newton'][k]} Newton iterations, step-44 "
                            f"{step44['newton_iterations'][k]} (+{extra} allowed)")
    print(f"step-44's indentation block, top point u_y in m; tolerance {tolerance:.0e} ({ref['tolerance']['source']})")
    benchlib.table(["t", "step-44 (direct)", "suturesim", "rel. diff.", "digits",
                    "Newton step-44", "Newton suturesim"], rows)
    exact_last = abs(u["exact"][-1] / u["newton"][-1] - 1)
    print(f"Newton iterations in total: step-44 {sum(step44['newton_iterations'])}, suturesim "
          f"{sum(its['newton'])}; with the exact update {sum(its['exact'])} in {len(its['exact'])} steps "
          f"({' '.join(map(str, its['exact']))}), final u_y {exact_last:.1e} relative from the default's. "
          f"Wall time of the runs {walls['newton']:.2f} s and {walls['exact']:.2f} s "
          f"(run_step44.sh times both programs back to back)")
    if not args.no_figure:
        figure(ref, u, its, out / "indentation_block")
    benchlib.verdict(failures)


def figure(ref, u, its, stem):
    plt = benchlib.pyplot()
    t = ref["step44"]["load_steps"]
    step44 = ref["step44"]["direct_static_condensation"]
    fig, (a, b) = plt.subplots(1, 2, figsize=(8, 3.2))
    a.plot(t, [-1e3 * v for v in step44["top_displacement_y"]], "o", mfc="none", color="k", label="step-44")
    a.plot(t, [-1e3 * v for v in u["newton"]], "-", color="tab:red", label="suturesim")
    a.set_xlabel("load factor (400 MPa at 1)")
    a.set_ylabel("top point $-u_y$ [mm]")
    a.legend(fontsize=7)
    a.grid(alpha=0.3)
    width = 0.025
    b.bar([x - width for x in t], step44["newton_iterations"], width, color="k", label="step-44")
    b.bar(t, its["newton"], width, color="tab:red", label="suturesim, p~ J~ Newton unknowns")
    b.axhline(sum(its["exact"]) / len(t), color="tab:grey", ls="--",
              label=f"suturesim, p~ J~ from u: mean per step ({sum(its['exact'])} in all)")
    b.set_xlabel("load factor")
    b.set_ylabel("Newton iterations")
    b.legend(fontsize=7)
    b.grid(alpha=0.3, axis="y")
    fig.tight_layout()
    benchlib.save_figure(fig, stem)


if __name__ == "__main__":
    main()
