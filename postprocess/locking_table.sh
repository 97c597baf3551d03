#!/usr/bin/env bash
# Cook's membrane at nu = 0.4999: tip displacement u_y (mm) under refinement for plain
# displacement elements and the mixed (u-p-J) formulation. Usage:
#   postprocess/locking_table.sh [path/to/suturesim] [output folder]
set -euo pipefail
bin=${1:-build/suturesim}
out=${2:-output/locking}
mkdir -p "$out"
scene=$(dirname "$0")/../benchmarks/cook_membrane/cook_membrane.prm
printf '%-4s %14s %14s %14s %14s\n' n "Q1 displ." "Q1-P0 mixed" "Q2 displ." "Q2-P1 mixed"
for n in 2 4 8 16 32; do
  row=$(printf '%-4s' $n)
  for cfg in "1 displacement" "1 mixed" "2 displacement" "2 mixed"; do
    set -- $cfg
    dir=$out/n${n}_q$1_$2
    "$bin" "$scene" --output "$dir" --set "Mesh/Elements per edge=$n" \
      --set "Tissue/Element degree=$1" --set "Tissue/Formulation=$2" \
      --set "Tissue/Material/Poisson ratio=0.4999" > "$dir.log" 2>&1 || true
    v=$(/usr/bin/python3 -c "import json,sys; s=json.load(open('$dir/summary.json')); print('%.4f' % (1e3*s['metrics']['tip_displacement_y']) if s['status']=='completed' else 'failed')" 2>/dev/null || echo failed)
    row+=$(printf ' %14s' "$v")
  done
  echo "$row"
done
