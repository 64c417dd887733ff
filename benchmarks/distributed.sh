#!/bin/sh
# Scaling of distributed runs (mpirun -np N warpchol FILE.prm) on the torus pull refined to
# 1.2 million tetrahedra (parameters/torus_pull_1m.prm), from the repository root after
# .ci/setup:
#
#   sh benchmarks/distributed.sh            # about 6 minutes on 2 cores
#
# - strong scaling: 1.23M tets on 1 and 2 ranks;
# - weak scaling: 0.61M tets (10 toroidal cells) on 1 rank against 1.23M on 2;
# - WCC (threshold 0.3) against exact corotation on 2 ranks, both with Trilinos AMG-CG;
# - MUMPS (PETSc) against AMG-CG on the 60k-unknown torus, 1 and 2 ranks.
# One thread per rank, BLAS on one thread. Each run's summary goes to
# doc/distributed/RUN.txt, the table to doc/distributed/scaling.md; STEPS=N (default 5)
# steps per run. On a shared machine compare runs of one invocation only.
set -e
export OMP_THREAD_LIMIT=1 OPENBLAS_NUM_THREADS=1
# OpenMPI refuses root without these; they change nothing for other users.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
steps=${STEPS:-5}
root=$(pwd)
results=doc/distributed
work=output/distributed_benchmark
mkdir -p "$results" "$work"

# run NAME RANKS SETTINGS: the 1M scene with SETTINGS (prm lines) on RANKS ranks.
run() {
  name=$1 ranks=$2 settings=$3
  printf 'include %s/parameters/torus_pull_1m.prm\n%s\nsubsection Time stepping\n  set Number of steps = %s\nend\nsubsection Output\n  set Directory = %s\n  set Scene = %s\n  set Write log = false\n  set Progress = off\nend\n' \
    "$root" "$settings" "$steps" "$root/$work" "$name" > "$work/$name.prm"
  echo "== $name: $ranks rank(s)" >&2
  /usr/bin/time -f "wall %e s, peak memory of a rank %M kB" mpirun -np "$ranks" build/warpchol "$work/$name.prm" --distributed \
    > "$results/$name.txt" 2> "$work/$name.time"
  cat "$work/$name.time" >> "$results/$name.txt"
}

half='subsection Mesh
  set Torus toroidal cells = 10
end'
small='subsection Mesh
  set Torus toroidal cells = 16
  set Torus refinements = 2
end'
wcc='subsection Model
  set Type = warp_canceling
  set Rerotation threshold = 0.3
end'
mumps='subsection Distributed
  set Linear solver = mumps
end'

run corotational_0.6M_np1 1 "$half"
run corotational_1.2M_np1 1 ""
run corotational_1.2M_np2 2 ""
run wcc_1.2M_np2 2 "$wcc"
run corotational_60k_amg_np1 1 "$small"
run corotational_60k_amg_np2 2 "$small"
run corotational_60k_mumps_np1 1 "$small
$mumps"
run corotational_60k_mumps_np2 2 "$small
$mumps"

# The table: per run, the slowest rank's seconds per step in each stage.
{
  echo "| run | tets | set-up s | step s (max rank) | rotations | assembly | estimate | AMG set-up / factorization | solve | CG its | wall s | peak kB per rank |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
  for file in "$results"/*_np[12].txt; do
    awk -v name="$(basename "$file" .txt)" '
      /tetrahedra, / { tets = $1 }
      /set-up .* per step/ { setup = $2; split($0, a, "per step "); split(a[2], b, " / "); step = b[3]; sub(/ s.*/, "", step) }
      /mean CG iterations/ { match($0, /mean CG iterations [0-9.]+/); its = substr($0, RSTART + 19, RLENGTH - 19) }
      $1 == "rotations" { rot = $4 } $1 == "assembly" { asm = $4 } $1 == "error" { est = $5 }
      $1 == "factorization" { fac = $4 } $1 == "solve" { sol = $4 }
      /^wall/ { wall = $2; peak = $(NF - 1) }
      END { printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", name, tets, setup, step, rot, asm, est, fac, sol, its, wall, peak }' "$file"
  done
} > "$results/scaling.md"
cat "$results/scaling.md"
