#!/bin/bash
# Builds deal.II's step-44 from Debian's libdeal.ii-doc examples and runs it beside
# suturesim on the same problem, back to back, to obtain reference.json's values and the
# Newton and wall-time comparison of README.md.
#
#   benchmarks/indentation_block/run_step44.sh build/suturesim [WORKDIR] [REPEATS]
#
# Needs libdeal.ii-doc (installed with apt-get when missing, which needs root). Both
# programs run with one BLAS thread; step-44 assembles with deal.II's threads (both
# cores) as shipped, suturesim on one core. Prints step-44's top-point displacement per
# load step (16 digits) and Newton iterations, and the median wall time of REPEATS
# (default 3) alternating runs of: step-44 as shipped (CG + SSOR), step-44 with its
# direct solver and static condensation, suturesim (p~, J~ Newton unknowns) and
# suturesim with the exact update.
set -euo pipefail
SUTURESIM=$(realpath "${1:?usage: run_step44.sh SUTURESIM [WORKDIR] [REPEATS]}")
SCENE=$(realpath "$(dirname "$0")/indentation_block.prm")
W=${2:-$(mktemp -d -t step44.XXXXXX)}
REPEATS=${3:-3}
EXAMPLE=/usr/share/doc/libdeal.ii-doc/examples/step-44
mkdir -p "$W"
cd "$W"
echo "work folder: $PWD"
[ -d "$EXAMPLE" ] || apt-get install -y libdeal.ii-doc > /dev/null

# step-44 as shipped, plus a print of the top point's vertical displacement after each
# load step (step-44 does not print it; nothing else is changed)
rm -rf src build
mkdir src build
cp "$EXAMPLE"/* src/
for f in src/*.gz; do [ -e "$f" ] && gunzip -f "$f"; done
(cd src && patch -s step-44.cc << 'PATCH'
--- step-44.cc
+++ step-44.cc
@@ -1125,6 +1125,15 @@
         // \varDelta \mathbf{\Xi}$...
         solve_nonlinear_timestep(solution_delta);
         solution_n += solution_delta;
+        {
+          Point<dim> top;
+          top[1] = parameters.scale;
+          Vector<double> value(n_components);
+          VectorTools::point_value(dof_handler, solution_n, top, value);
+          std::cout << std::setprecision(16) << std::scientific << "TOPPOINT "
+                    << time.get_timestep() << ' ' << value[1] << std::endl
+                    << std::defaultfloat << std::setprecision(6);
+        }
 
         // ...and plot the results before moving on happily to the next time
         // step:
PATCH
)
start=$(date +%s)
(cd build && cmake -DDEAL_II_DIR=/usr/share/cmake/deal.II -DCMAKE_BUILD_TYPE=Release ../src > cmake.log 2>&1 &&
  make -j"$(nproc)" > make.log 2>&1)
echo "step-44 built in $(($(date +%s) - start)) s"
sed -e 's/\(set Use static condensation *=\).*/\1 true/' -e 's/\(set Solver type *=\).*/\1 Direct/' \
  src/parameters.prm > direct.prm
cp src/parameters.prm shipped.prm

export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
# wall time in seconds of one command, its output into the named log
timed() {
  local log=$1
  shift
  local t0 t1
  t0=$(date +%s.%N)
  "$@" > "$log" 2>&1
  t1=$(date +%s.%N)
  echo "$t1 - $t0" | bc
}
step44() { # configuration name; step-44 reads parameters.prm from its working folder
  mkdir -p "run-$1"
  cp "$1.prm" "run-$1/parameters.prm"
  (cd "run-$1" && timed out.txt ../build/step-44)
}
declare -A times
for r in $(seq "$REPEATS"); do
  times[shipped]+="$(step44 shipped) "
  times[direct]+="$(step44 direct) "
  times[newton]+="$(timed suturesim-newton.log "$SUTURESIM" "$SCENE" --output out-newton) "
  times[exact]+="$(timed suturesim-exact.log "$SUTURESIM" "$SCENE" --output out-exact --set 'Tissue/Mixed update=exact') "
done

median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
for c in shipped direct; do
  echo "== step-44, $c parameters ($(grep -o 'Number of degrees of freedom: [0-9]*' "run-$c/out.txt" | head -1))"
  awk '/^Timestep/ {step = $2} /CONVERGED/ {its[step] = $1; total += $1}
       END {printf "   Newton iterations per load step:"; for (s = 1; s <= step; ++s) printf " %s", its[s];
            print ", total " total}' "run-$c/out.txt"
  grep '^TOPPOINT' "run-$c/out.txt" | awk '{printf "   step %2d: u_y(0, 1 mm, 0) = %s m\n", $2, $3}'
done
for c in newton exact; do
  echo "== suturesim, mixed update $c: Newton iterations per load step:" \
    "$(/usr/bin/python3 -c 'import json, sys; s = json.load(open(sys.argv[1])); its = [x["newton_iterations"] for x in s["steps"][1:]]; print(*its, ", total", sum(its))' "out-$c/summary.json")"
done
echo "== median wall time of $REPEATS runs each (s), alternating:"
for c in shipped direct newton exact; do
  printf '   %-8s %6.2f   (%s)\n' "$c" "$(echo "${times[$c]}" | median)" "${times[$c]}"
done
echo "   suturesim (newton) / step-44 direct: $(echo "$(echo "${times[newton]}" | median) / $(echo "${times[direct]}" | median)" | bc -l | cut -c1-5)"
