#!/bin/sh
# The error-against-time study of the README (issue 8): warpchol-threshold-sweep on the
# fine torus, SOFA's liver and SOFA's raptor. Per scene it writes into doc/study/ the
# table (SCENE.txt), the CSV (SCENE.csv), the gnuplot script (SCENE.gp) and the plot
# (SCENE.png: error against seconds per step, the Pareto front drawn).
#   sh benchmarks/study.sh          (after sh .ci/setup; about 3 minutes on 2 cores)
# Environment: BUILD (default build), OUT (default doc/study), THREADS (default 1).
set -eu
cd "$(dirname "$0")/.."
build=${BUILD:-build}
out=${OUT:-doc/study}
threads=${THREADS:-1}
mkdir -p "$out"
command -v gnuplot > /dev/null ||
  echo "study.sh: no gnuplot (Debian: apt-get install gnuplot-nox): tables, CSV and scripts only"

# Threshold 0 is left out: it is the exact run to rounding (a test), and its 1e-14 would
# stretch the log scale over ten empty decades.
partial_thresholds=0.03,0.1,0.3,1,3,inf
strategies=delayed_top,preconditioned,auto
strategy_thresholds=0.3,1,inf
target_errors=0.003,0.01,0.03

for scene in torus_pull_fine liver raptor; do
  echo "== $scene"
  "$build/warpchol-threshold-sweep" "parameters/$scene.prm" --threads "$threads" \
    --thresholds "$partial_thresholds" --strategies "$strategies" \
    --strategy-thresholds "$strategy_thresholds" --target-errors "$target_errors" --csv "$out/$scene.csv" > "$out/$scene.txt"
  cat "$out/$scene.txt"
done
