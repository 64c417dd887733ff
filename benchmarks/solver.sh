#!/bin/sh
# The solver benchmarks (doc/benchmarks.md; issues 2 and 3), against CHOLMOD in the same process.
#   sh benchmarks/solver.sh            (after sh .ci/setup; writes output/benchmarks/)
# Environment: BUILD (default build), OUT (default output/benchmarks), REPEAT (default 5).
set -eu
cd "$(dirname "$0")/.."
build=${BUILD:-build}
out=${OUT:-output/benchmarks}
repeat=${REPEAT:-5}
mkdir -p "$out"

# Tet elasticity matrices A = M + dt^2 K of the report's torus, assembled with deal.II.
for dofs in 10000 25000 60000; do
  [ -f "$out/torus_$dofs.mtx" ] || "$build/warpchol-torus-matrix" --dofs "$dofs" --output "$out/torus_$dofs.mtx"
done

echo "== issue 2: bcsstk16, AMD, column by column (the report: up 0.0815 s, left 0.0907 s, fill 253.41 %)"
for method in up left; do
  "$build/warpchol-factor" tests/data/bcsstk16.mtx --ordering amd --method "$method" --repeat "$repeat"
done

echo "== issue 3: full factorization, supernodal, 1 thread, against CHOLMOD supernodal"
for matrix in tests/data/bcsstk16.mtx "$out/torus_10000.mtx" "$out/torus_25000.mtx" "$out/torus_60000.mtx"; do
  for ordering in metis amd; do
    "$build/warpchol-factor" "$matrix" --ordering "$ordering" --method supernodal --compare cholmod \
      --changed-fraction 0 --repeat "$repeat"
  done
done

echo "== issue 3: threads on the largest matrix"
for threads in 1 2; do
  "$build/warpchol-factor" "$out/torus_60000.mtx" --ordering metis --method supernodal --threads "$threads" \
    --changed-fraction 0 --repeat "$repeat"
done

echo "== issue 3: partial refactorization against the changed fraction"
for ordering in metis amd; do
  "$build/warpchol-sweep" "$out/torus_25000.mtx" --ordering "$ordering" --method left --repeat "$repeat"
done
