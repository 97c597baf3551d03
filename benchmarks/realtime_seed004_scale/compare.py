#!/usr/bin/python3
"""Step-time statistics of the realtime path at seed 004's scale (reference.json: the
seed's anchor, the targets, the configurations). A performance record: no pass/fail on
time; exits 1 only when a run failed or did not make every haptic step.

  /usr/bin/python3 benchmarks/realtime_seed004_scale/compare.py OUTPUT --run build/suturesim [--all]
  /usr/bin/python3 benchmarks/realtime_seed004_scale/compare.py OUTPUT [--all]   # runs there

OUTPUT/<configuration> for the scene as shipped, with --all for every configuration of
reference.json (the README's integrator / suture pairs). Prints median, p99 and max step
time, deadline misses and the processor the run recorded; draws
OUTPUT/realtime_seed004_scale.png/.pdf (median and p99 against the 1 ms deadline).
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import benchlib  # noqa: E402


def main():
    parser = benchlib.arguments(__doc__)
    parser.add_argument("--all", action="store_true", help="every configuration, not only the shipped one")
    args = parser.parse_args()
    ref = benchlib.reference(__file__)
    configurations = ref["configurations"] if args.all else ref["configurations"][:1]
    out = Path(args.output)
    rows, stats, failures = [], [], []
    for c in configurations:
        run = out / c["name"]
        if args.run:
            benchlib.run(args.run, benchlib.folder_of(__file__) / ref["scene"], run, c["settings"])
        s = benchlib.summary(run)
        m = s["metrics"]
        if s["status"] != "completed" or m.get("steps") != ref["expected_steps"]:
            failures.append(f"{c['name']}: status {s['status']}, {m.get('steps')} of {ref['expected_steps']} steps")
        rows.append([c["what"], s["realtime"]["substeps"], f"{m['step_time_median_us']:.0f}",
                     f"{m['step_time_p99_us']:.0f}", f"{m['step_time_max_us']:.0f}", m["deadline_misses"],
                     s.get("machine", "?")])
        stats.append((c["name"], m["step_time_median_us"], m["step_time_p99_us"]))
    anchor, targets = ref["anchor"], ref["targets"]
    print(f"anchor: {anchor['ms_per_frame']} ms per frame on {anchor['tetrahedra']} tetrahedra ({anchor['source']}); "
          f"target median <= {targets['median_us']} us, stretch <= {targets['stretch_median_us']} us (not checked)")
    benchlib.table(["integrator / suture", "substeps", "median us", "p99 us", "max us", "deadline misses", "machine"], rows)
    if not args.no_figure:
        figure(stats, targets, out / "realtime_seed004_scale")
    benchlib.verdict(failures)


def figure(stats, targets, stem):
    plt = benchlib.pyplot()
    fig, ax = plt.subplots(figsize=(6, 3))
    x = range(len(stats))
    ax.bar([i - 0.2 for i in x], [s[1] for s in stats], 0.4, label="median")
    ax.bar([i + 0.2 for i in x], [s[2] for s in stats], 0.4, label="p99")
    ax.axhline(targets["median_us"], color="k", ls="--", lw=1, label="1 kHz deadline")
    ax.axhline(targets["stretch_median_us"], color="k", ls=":", lw=1, label="stretch goal")
    ax.set_xticks(list(x))
    ax.set_xticklabels([s[0] for s in stats], rotation=20, ha="right", fontsize=7)
    ax.set_ylabel("step time [us]")
    ax.set_yscale("log")
    ax.legend(fontsize=7)
    benchlib.save_figure(fig, stem)


if __name__ == "__main__":
    main()
