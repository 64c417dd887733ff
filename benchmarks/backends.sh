#!/bin/sh
# The peers' comparison (doc/peers.md; issue 9): every backend (Solver/Backend) on the same
# scene in one run of warpchol-threshold-sweep, against warpchol's configurations.
# Per scene it writes into doc/backends/ the table (SCENE.txt, with the machine's dgemm
# rate), the CSV (SCENE.csv), the gnuplot script (SCENE.gp) and the plot (SCENE.png: error
# against seconds per step).
#   sh benchmarks/backends.sh        (after sh .ci/setup; about 35 minutes on 2 cores, 17 of them Eigen's SimplicialLLT on 60k unknowns)
# Environment: BUILD (default build), OUT (default doc/backends), SCENES (default
# "torus_pull_fine torus_pull_60k torus_swing"), BACKENDS (default all; for instance
# cholmod,umfpack,eigen_cholmod,trilinos_amg_cg,warp_preconditioned_cg leaves out Eigen's
# SimplicialLLT, which takes about 100 s a step at 60k unknowns).
set -eu
cd "$(dirname "$0")/.."
build=${BUILD:-build}
out=${OUT:-doc/backends}
scenes=${SCENES:-"torus_pull_fine torus_pull_60k torus_swing"}
backends=${BACKENDS:-all}
mkdir -p "$out"
command -v gnuplot > /dev/null ||
  echo "backends.sh: no gnuplot (Debian: apt-get install gnuplot-nox): tables, CSV and scripts only"
# One thread for every library: CHOLMOD's OpenMP and OpenBLAS's threads would otherwise
# take the second core from the others (the sweep also restarts itself so).
export OMP_THREAD_LIMIT=1 OPENBLAS_NUM_THREADS=1

for scene in $scenes; do
  echo "== $scene"
  # warpchol: WCC partial (direct), its preconditioned strategies with and without re-rotations,
  # a target error of 1 %; the peers: the direct ones and the iterative ones at a tight and
  # a loose tolerance.
  "$build/warpchol-threshold-sweep" "parameters/$scene.prm" --threads 1 --thresholds 0.3,1 \
    --strategies auto,preconditioned --strategy-thresholds 1,inf --target-errors 0.01 \
    --backends "$backends" --peer-tolerances 1e-6,1e-3 --csv "$out/$scene.csv" > "$out/$scene.txt"
  cat "$out/$scene.txt"
done
