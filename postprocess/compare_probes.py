#!/usr/bin/python3
"""Displacement error of realtime runs against an accurate (FE) run at the probe points.

Usage: /usr/bin/python3 postprocess/compare_probes.py REFERENCE_DIR RUN_DIR [RUN_DIR...]

Reads metrics.<probe>_displacement_{x,y,z} (m) from each run's summary.json: the final
state. For every probe of the reference and every run that has it, prints the
reference displacement and the run's error |u - u_ref| / |u_ref| (relative to the
largest reference displacement for probes that barely move, marked *), and writes the
table as probe_comparison.csv in the first run's folder. A run's label is its folder
name with its model settings from summary.json.
"""
import csv
import json
import math
import sys
from pathlib import Path


def probes(run):
    metrics = json.load(open(run / "summary.json"))["metrics"]
    names = sorted({k[: -len("_displacement_x")] for k in metrics if k.endswith("_displacement_x")})
    return {n: [metrics[f"{n}_displacement_{c}"] for c in "xyz"] for n in names}


def label(run):
    summary = json.load(open(run / "summary.json"))
    rt = summary.get("realtime")
    if not rt:
        return f"{run.name} ({summary.get('model', '?')})"
    return f"{run.name} ({rt.get('tissue_model')}, {rt.get('integrator')})"


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    reference = Path(sys.argv[1])
    runs = [Path(a) for a in sys.argv[2:]]
    ref = probes(reference)
    if not ref:
        sys.exit(f"{reference}/summary.json has no probe displacements")
    scale = max(math.dist(u, (0, 0, 0)) for u in ref.values())
    table = []
    for name, u_ref in ref.items():
        norm = math.dist(u_ref, (0, 0, 0))
        small = norm < 0.05 * scale
        row = {"probe": name, "reference |u| [m]": norm}
        for run in runs:
            u = probes(run).get(name)
            if u is None:
                row[label(run)] = float("nan")
                continue
            row[label(run)] = math.dist(u, u_ref) / (scale if small else norm)
        row["relative to"] = "max |u_ref| *" if small else "|u_ref|"
        table.append(row)

    columns = list(table[0].keys())
    print(f"reference: {label(reference)}")
    print("| " + " | ".join(columns) + " |")
    print("|" + "---|" * len(columns))
    for row in table:
        cells = [f"{v:.3g}" if isinstance(v, float) else v for v in row.values()]
        print("| " + " | ".join(cells) + " |")
    out = runs[0] / "probe_comparison.csv"
    with open(out, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=columns)
        writer.writeheader()
        writer.writerows(table)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
