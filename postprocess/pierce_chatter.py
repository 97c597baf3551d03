#!/usr/bin/python3
"""How much the pierce points of stitch runs chatter between stick and slip:

  /usr/bin/python3 postprocess/pierce_chatter.py RUN [RUN ...] [--from T0] [--to T1] [--jump N]

Reads each run's forces.csv and counts, per hole and within [T0, T1] s (default 2 to
5 s, from the tail's lay-down to before closure), the recorded steps where the hole's
normal force changes by more than N newtons (default 0.5) from the previous row, and
where its friction changes sign. A hole that slides smoothly has none of either; seed
002's thread laid straight through its holes jumps each time a sliding point passes a
node (docs/interrupted_stitch.md, "The realtime thread's links"). Prints one Markdown
row per run. Rows are per recorded step, so compare runs of one rate.
"""
import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from plot_forces import column, read  # noqa: E402
from plot_pierce_loads import holes  # noqa: E402


def counts(header, data, hole, start, end, jump):
    """Normal-force jumps and friction sign changes of @p hole within [start, end]."""
    time = column(header, data, "time")
    normal = column(header, data, f"pierce_{hole}_normal_force")
    friction = column(header, data, f"pierce_{hole}_friction_force")
    rows = [k for k in range(1, len(time)) if start <= time[k] <= end]
    jumps = sum(1 for k in rows if abs(normal[k] - normal[k - 1]) > jump)
    flips = sum(1 for k in rows if friction[k] * friction[k - 1] < 0)
    return jumps, flips


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", nargs="+", type=Path, help="run folders with a forces.csv")
    parser.add_argument("--from", dest="start", type=float, default=2.0, help="window start (s)")
    parser.add_argument("--to", dest="end", type=float, default=5.0, help="window end (s)")
    parser.add_argument("--jump", type=float, default=0.5, help="normal-force change that counts (N)")
    args = parser.parse_args()
    if not args.end > args.start or not args.jump > 0:
        print("pierce_chatter.py: need --to > --from and --jump > 0", file=sys.stderr)
        return 2
    tables = []
    for run in args.runs:
        if not (run / "forces.csv").is_file():
            print(f"pierce_chatter.py: {run}/forces.csv: no such file", file=sys.stderr)
            return 2
        header, data = read(run)
        if column(header, data, "time") is None:
            print(f"pierce_chatter.py: {run}/forces.csv: no time column", file=sys.stderr)
            return 2
        tables.append((run, header, data))
    print("| run | per hole: normal-force jumps / friction sign changes |")
    print("|---|---|")
    for run, header, data in tables:
        cells = []
        for hole in holes(header):
            jumps, flips = counts(header, data, hole, args.start, args.end, args.jump)
            cells.append(f"hole {hole}: {jumps} / {flips}")
        print(f"| {run.name} | {', '.join(cells) if cells else 'no holes'} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
