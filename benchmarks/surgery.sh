#!/bin/sh
# The cost of cuts, grasps and material changes (issue 19): warpchol-surgery on the scenes
# with changes. Per scene it writes doc/surgery/SCENE.txt (each change against a full
# factorization and CHOLMOD analyzing anew; whole runs against exact corotation by warpchol
# and CHOLMOD and against the stale rest factor with CG) and SCENE.csv.
#   sh benchmarks/surgery.sh        (after sh .ci/setup; about 10 minutes on 2 cores)
# Environment: BUILD (default build), OUT (default doc/surgery), SCENES (default: all four).
set -eu
cd "$(dirname "$0")/.."
build=${BUILD:-build}
out=${OUT:-doc/surgery}
scenes=${SCENES:-"liver_cut torus_cut grasp_release torus_cauterize"}
mkdir -p "$out"
export OMP_THREAD_LIMIT=1 OPENBLAS_NUM_THREADS=1
for scene in $scenes; do
  echo "== $scene"
  taskset -c 0 "$build/warpchol-surgery" "parameters/$scene.prm" --repeat 2 --csv "$out/$scene.csv" > "$out/$scene.txt.tmp"
  mv "$out/$scene.txt.tmp" "$out/$scene.txt"
  cat "$out/$scene.txt"
done
