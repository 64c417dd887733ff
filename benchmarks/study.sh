#!/bin/sh
# The error-against-time study (doc/strategies.md; issues 8 and 18): warpchol-threshold-sweep on
# the compact scenes (the fine torus, SOFA's liver and raptor) and the thin bodies (a
# cantilevered rod, a plate held at an edge, a vessel pulled by the tool; each at a
# realistic stiffness and overloaded), on one core and on two. Per scene and core count it
# writes into doc/study/ the table (SCENE-tN.txt), the CSV (SCENE-tN.csv), the gnuplot
# script (SCENE-tN.gp) and the plot (SCENE-tN.png: error against seconds per step), and the
# summary of all of them in doc/study/summary.md: per scene, the exact path's seconds per
# step, the fastest run at <= 1 % error, the automatic strategy and the background refresh;
# each table also has the exact run on CHOLMOD (the peer, refactoring every step).
#   sh benchmarks/study.sh          (after sh .ci/setup; about 40 minutes on 2 cores)
# Environment: BUILD (default build), OUT (default doc/study), THREADS (default "1 2"),
# SCENES (default: all of the above).
# Each run is pinned to as many cores as it has threads (taskset): one thread means one
# core, also for the background refresh, whose second thread then shares it.
set -eu
cd "$(dirname "$0")/.."
build=${BUILD:-build}
out=${OUT:-doc/study}
thread_counts=${THREADS:-"1 2"}
scenes=${SCENES:-"torus_pull_fine liver raptor beam beam_overloaded plate plate_overloaded tube tube_overloaded"}
mkdir -p "$out"
command -v gnuplot > /dev/null ||
  echo "study.sh: no gnuplot (Debian: apt-get install gnuplot-nox): tables, CSV and scripts only"
# As every comparison of this project: one BLAS thread, no OpenMP regions of CHOLMOD's.
export OMP_THREAD_LIMIT=1 OPENBLAS_NUM_THREADS=1

# Threshold 0 is left out: it is the exact run to rounding (a test), and its 1e-14 would
# stretch the log scale over ten empty decades.
partial_thresholds=0.03,0.1,0.3,1,inf
strategies=delayed_top,preconditioned,auto,background
strategy_thresholds=0.3,1,inf
target_errors=0.003,0.01

summary="$out/summary.md"
{
  echo "# The study: seconds per step at <= 1 % trajectory error"
  echo
  echo "Written by \`sh benchmarks/study.sh\`; one row per scene and core count. exact: the"
  echo "corotational model, assembled and factored every step (the fast exact path); best:"
  echo "the fastest run of the sweep at <= 1 % max trajectory error; auto and background: the"
  echo "automatic strategy's and the background refresh's best runs there. Speed-ups against"
  echo "exact in the same sweep."
  echo
  echo "| scene | cores | exact s/step | best at <= 1 % | auto | background |"
  echo "|---|---|---|---|---|---|"
} > "$summary.tmp"

for scene in $scenes; do
  for threads in $thread_counts; do
    cores=$(seq -s, 0 $((threads - 1)))
    echo "== $scene, $threads thread(s) (cores $cores)"
    table="$out/$scene-t$threads.txt"
    taskset -c "$cores" "$build/warpchol-threshold-sweep" "parameters/$scene.prm" --threads "$threads" \
      --thresholds "$partial_thresholds" --strategies "$strategies" \
      --strategy-thresholds "$strategy_thresholds" --target-errors "$target_errors" \
      --backends cholmod \
      --csv "$out/$scene-t$threads.csv" > "$table.tmp"
    mv "$table.tmp" "$table"
    cat "$table"
    field() { grep "^$1" "$table" | sed "s/^$1//"; }
    echo "| $scene | $threads | $(field 'exact (corotational): ') | $(field 'best at <= 1 % error: ') |" \
         "$(field 'auto at <= 1 % error: ') | $(field 'background at <= 1 % error: ') |" >> "$summary.tmp"
  done
done
mv "$summary.tmp" "$summary"
cat "$summary"
