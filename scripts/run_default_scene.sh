#!/usr/bin/env bash
# The default scene, the interrupted stitch (parameters/stitch_interrupted.prm), in both
# model paths, and its figures:
#   scripts/run_default_scene.sh [path/to/suturesim] [output folder]
# realtime: the scene as shipped (output folder); accurate: the same file with
# Model = accurate, at the resolution of its "subsection Model accurate" (Q1-P0
# hexahedra of 2 mm, 20 ms steps; output folder + "_accurate"; several minutes on
# 2 cores). Then the curves of both, overlaid (stitch_curves.{png,pdf}), and the
# realtime run's picture (scene.{png,pdf}), in the realtime run's folder.
# docs/interrupted_stitch.md explains the settings.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${1:-build/suturesim}
out=${2:-output/default}
scene="$here/../parameters/stitch_interrupted.prm"
"$bin" "$scene" --output "$out"
OPENBLAS_NUM_THREADS=1 "$bin" "$scene" --set Model=accurate --output "${out}_accurate"
/usr/bin/python3 "$here/../postprocess/plot_stitch.py" "$out" "${out}_accurate"
/usr/bin/python3 "$here/../postprocess/plot_scene.py" "$out"
