#!/bin/sh
# Every SIMD kernel on every target this CPU runs (issue 36), one thread, in one table per
# input: the solver's kernels (warpchol-solver-kernels: the update and downdate at ranks 1
# to 64 beside CHOLMOD's cholmod_updown, the 16- and 32-bit preconditioner solves, the
# double solve, the supernodal factorization) on the matrices of benchmarks/updates.sh;
# Gauss-Seidel on a kept W, whose product W lambda is a kernel (warpchol-contact-kernels);
# the element kernels (warpchol-kernels: ns per tet) on the study's scenes and SOFA's
# meshes. Each row gives its family's default target's time over the fastest target's,
# marked "slow" past 1.15. Writes doc/targets/kernels.md.
#   sh benchmarks/kernel_targets.sh      (after sh .ci/setup; about 15 minutes on 2 cores)
# Environment: BUILD (default build), OUT (default doc/targets), MATRICES, SCENES, REPEAT.
set -eu
cd "$(dirname "$0")/.."
build=${BUILD:-build}
out=${OUT:-doc/targets}
matrix_names=${MATRICES:-"torus_10k raptor torus_28k torus_60k"}
scenes=${SCENES:-"torus_pull_fine torus_pull_60k liver raptor cylinder"}
repeat=${REPEAT:-5}
matrices=output/benchmarks
mkdir -p "$out" "$matrices"
export OMP_THREAD_LIMIT=1 OPENBLAS_NUM_THREADS=1

# The matrices, made as benchmarks/updates.sh makes them.
for matrix in $matrix_names; do
  [ -f $matrices/$matrix.mtx ] && continue
  case $matrix in
    raptor) "$build/warpchol-torus-matrix" --mesh meshes/sofa_raptor_19409.vtu --output $matrices/raptor.mtx ;;
    torus_*) dofs=$(echo "$matrix" | sed 's/torus_\([0-9]*\)k/\1000/')
             "$build/warpchol-torus-matrix" --dofs "$dofs" --output $matrices/$matrix.mtx ;;
    *) echo "kernel_targets.sh: no recipe for the matrix '$matrix'" >&2; exit 2 ;;
  esac
done

report="$out/kernels.md.tmp"
{
  echo "# Every SIMD kernel on every target"
  echo
  echo "Written by \`sh benchmarks/kernel_targets.sh\`: each kernel timed on every SIMD target this"
  echo "CPU runs (forced as WARPCHOL_SIMD_TARGET forces it), one thread. \"default / fastest\": the"
  echo "kernel's family's default target (the update's and the assembly's: the widest; the others':"
  echo "AVX2 where the CPU has it) over the fastest target; \"slow\" marks a ratio past 1.15. The"
  echo "element kernels: each timed on the targets in turn, best of 3 rounds."
  echo
  echo "## The solver's kernels (ms)"
  for matrix in $matrix_names; do
    echo
    taskset -c 0 "$build/warpchol-solver-kernels" $matrices/$matrix.mtx --repeat "$repeat"
  done
  echo
  echo "## The contact kernel (ms)"
  echo
  taskset -c 0 "$build/warpchol-contact-kernels" --only gauss-seidel
  echo
  echo "## The element kernels (ns per tet)"
  for scene in $scenes; do
    echo
    echo '```'
    taskset -c 0 "$build/warpchol-kernels" parameters/$scene.prm
    echo '```'
  done
} > "$report"
mv "$report" "$out/kernels.md"
cat "$out/kernels.md"
