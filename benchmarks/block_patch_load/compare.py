#!/usr/bin/python3
"""The realtime tissue models against the FE model at the probes of the block under a
pressure patch (reference.json: the FE probe displacements, their source, tolerances).

  /usr/bin/python3 benchmarks/block_patch_load/compare.py OUTPUT --run build/suturesim
  /usr/bin/python3 benchmarks/block_patch_load/compare.py OUTPUT   # runs already there
  /usr/bin/python3 benchmarks/block_patch_load/compare.py --against FE_RUN RUN [RUN ...]

The first two: OUTPUT/accurate (the scene as shipped) and one folder per realtime
configuration of reference.json["realtime_runs"]. Prints |u - u_FE| / |u_FE| at each probe
(relative to the largest FE displacement for probes that barely move, marked *), checks
that OUTPUT/accurate reproduces the stored FE values, draws OUTPUT/block_patch_load.png/.pdf
and exits 1 when the FE run drifts beyond its regression tolerance or the converged
realtime model is off by more than the stated factor at the top centre.

--against: any runs against any FE run (e.g. coarse meshes); prints the same table,
writes probe_comparison.csv in the first run's folder and checks nothing.
"""
import argparse
import csv
import json
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import benchlib  # noqa: E402


def probes(run):
    """{probe: (u_x, u_y, u_z)} of a run's final state (metrics.<probe>_displacement_*)."""
    metrics = benchlib.summary(run)["metrics"]
    names = sorted({k[: -len("_displacement_x")] for k in metrics if k.endswith("_displacement_x")})
    return {n: [metrics[f"{n}_displacement_{c}"] for c in "xyz"] for n in names}


def label(run):
    summary = benchlib.summary(run)
    rt = summary.get("realtime")
    if not rt:
        return f"{Path(run).name} ({summary.get('model', '?')})"
    return f"{Path(run).name} ({rt.get('tissue_model')}, {rt.get('integrator')})"


def errors(reference, runs, labels=None):
    """Rows {probe, |u_ref|, label: relative error, ...} against reference probes; the
    columns are named by @p labels, else by label(run)."""
    labels = labels or [label(run) for run in runs]
    scale = max(math.dist(u, (0, 0, 0)) for u in reference.values())
    rows = []
    for name, u_ref in reference.items():
        norm = math.dist(u_ref, (0, 0, 0))
        small = norm < 0.05 * scale
        row = {"probe": name, "reference |u| [m]": norm}
        for run, column in zip(runs, labels):
            u = probes(run).get(name)
            row[column] = float("nan") if u is None else math.dist(u, u_ref) / (scale if small else norm)
        row["relative to"] = "max |u_ref| *" if small else "|u_ref|"
        rows.append(row)
    return rows


def print_rows(rows):
    columns = list(rows[0].keys())
    benchlib.table(columns, [[f"{v:.3g}" if isinstance(v, float) else v for v in r.values()] for r in rows])
    return columns


def against(fe, runs):
    """The ad hoc comparison of --against."""
    rows = errors(probes(fe), runs)
    print(f"reference: {label(fe)}")
    columns = print_rows(rows)
    out = Path(runs[0]) / "probe_comparison.csv"
    with open(out, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=columns)
        writer.writeheader()
        writer.writerows(rows)
    print(f"wrote {out}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folders", nargs="+", help="OUTPUT, or with --against the runs")
    parser.add_argument("--run", metavar="SUTURESIM", help="make the runs first with this binary")
    parser.add_argument("--against", metavar="FE_RUN", help="compare the given runs with this FE run")
    parser.add_argument("--no-figure", action="store_true")
    args = parser.parse_args()
    if args.against:
        return against(Path(args.against), [Path(f) for f in args.folders])

    ref = benchlib.reference(__file__)
    here = benchlib.folder_of(__file__)
    out = Path(args.folders[0])
    fe_run = out / "accurate"
    runs = [out / r["name"] for r in ref["realtime_runs"]]
    if args.run:
        benchlib.run(args.run, here / ref["scene"], fe_run)
        for r, folder in zip(ref["realtime_runs"], runs):
            benchlib.run(args.run, here / ref["scene"], folder, r["settings"])

    failures = []
    stored = ref["fe_reference"]["displacement_m"]
    tolerance = ref["fe_reference"]["regression_tolerance_m"]
    drift = max(math.dist(u, stored[p]) for p, u in probes(fe_run).items())
    print(f"FE run {fe_run} against the stored FE values: largest probe difference {drift:.2e} m "
          f"(tolerance {tolerance:g} m, {ref['fe_reference']['regression_how']})")
    if drift > tolerance:
        failures.append(f"the FE run differs from the stored FE values by {drift:.3e} m > {tolerance:g} m")

    labels = [r["what"] for r in ref["realtime_runs"]]
    rows = errors(stored, runs, labels)
    print("\nerror |u - u_FE| / |u_FE| at the probes (FE: reference.json)")
    print_rows(rows)
    check = ref["realtime_check"]
    u_fe = stored[check["probe"]][2]
    u_rt = probes(out / check["run"])[check["probe"]][2]
    ratio = abs(math.log(u_rt / u_fe)) if u_rt * u_fe > 0 else math.inf
    print(f"\n{check['run']}: u_z at {check['probe']} {u_rt:.4e} m against FE {u_fe:.4e} m "
          f"(|ln ratio| {ratio:.3f}, bound ln {check['max_factor']:g} = {math.log(check['max_factor']):.3f})")
    if ratio > math.log(check["max_factor"]):
        failures.append(f"{check['run']} off the FE model by more than a factor {check['max_factor']:g} at {check['probe']}")
    if not args.no_figure:
        figure(rows, labels, out / "block_patch_load")
    benchlib.verdict(failures)


def figure(rows, labels, stem):
    plt = benchlib.pyplot()
    fig, ax = plt.subplots(figsize=(6.5, 3.2))
    width = 0.8 / len(labels)
    for i, name in enumerate(labels):
        ax.bar([j + i * width for j in range(len(rows))], [r[name] for r in rows], width, label=name)
    ax.set_xticks([j + 0.4 - width / 2 for j in range(len(rows))])
    ax.set_xticklabels([r["probe"] for r in rows], fontsize=7)
    ax.set_ylabel("$|u - u_{FE}| / |u_{FE}|$")
    ax.legend(fontsize=6, loc="upper left", bbox_to_anchor=(1.02, 1))
    ax.grid(axis="y", alpha=0.3)
    benchlib.save_figure(fig, stem)


if __name__ == "__main__":
    main()
