#!/usr/bin/env bash
# Every figure of the README from fresh runs, one command:
#   postprocess/readme_figures.sh [path/to/suturesim] [output folder]
# Runs the stitch in both paths (scripts/run_default_scene.sh: the realtime scene as
# shipped and the accurate one, several minutes) and draws its picture (plot_scene.py)
# and curves (plot_stitch.py, both paths overlaid), then both paths through needle_pass
# (needle_pass_figure.sh, several minutes), and copies the PNGs the README shows into
# docs/figures/.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${1:-build/suturesim}
out=${2:-output/readme}
mkdir -p "$out" "$here/../docs/figures"
"$here/../scripts/run_default_scene.sh" "$bin" "$out/stitch" > "$out/stitch.log" 2>&1
"$here/needle_pass_figure.sh" "$bin" "$out/needle_pass"
cp "$out/stitch/scene.png" "$here/../docs/figures/stitch_scene.png"
cp "$out/stitch/stitch_curves.png" "$here/../docs/figures/stitch_curves.png"
cp "$out/needle_pass/realtime/needle_forces.png" "$here/../docs/figures/needle_pass_forces.png"
echo "figures in $out and docs/figures/"
