#!/usr/bin/env bash
# Both model paths through parameters/needle_pass.prm and their force curves side by
# side (issue 5). Usage:
#   postprocess/needle_pass_figure.sh [path/to/suturesim] [output folder]
# Writes <output>/realtime and <output>/accurate, and the overlaid figure
# <output>/realtime/needle_forces.{png,pdf}. The accurate run carries the Cosserat
# suture through the pierce points (Bodies = tissue and suture, as in the file) on Q1
# hexahedra of 2 mm with 20 ms load steps (several minutes); the realtime run is the
# scene as shipped.
set -euo pipefail
bin=${1:-build/suturesim}
out=${2:-output/needle_pass_both}
scene=$(dirname "$0")/../parameters/needle_pass.prm
mkdir -p "$out"
"$bin" "$scene" --output "$out/realtime" > "$out/realtime.log" 2>&1
"$bin" "$scene" --output "$out/accurate" --set Model=accurate \
  --set "Time/End time=3.2" --set "Time/Output interval=0.1" \
  > "$out/accurate.log" 2>&1
/usr/bin/python3 "$(dirname "$0")/plot_forces.py" "$out/realtime" "$out/accurate"
for run in realtime accurate; do
  /usr/bin/python3 - "$out/$run/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
m = s["metrics"]
print(f"{s['model']:9s} puncture entry {m.get('puncture_force_entry', float('nan')):.4f} N, "
      f"exit {m.get('puncture_force_exit', float('nan')):.4f} N, peak pull {m['peak_pull_force']:.4f} N, "
      f"wall {s.get('wall_time_seconds', float('nan')):.1f} s")
PY
done
