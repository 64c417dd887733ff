#!/bin/sh
# Rank-k updates of the factor (issue 25): warpchol's update and downdate against its
# partial refactorization of the same columns, a full factorization and CHOLMOD's
# cholmod_updown on its simplicial LDL^T factor of the same matrix and permutation, on FE
# matrices of 10k to 60k unknowns and ranks 1 to 64 (a grasp-like change: a penalty on the
# dofs of the vertices around a random one). One thread, on the update family's default
# SIMD target, then the update again on each target forced (AVX-512, AVX2). Writes
# doc/updates/table.md and the raw key=value lines (doc/updates/runs.txt).
#   sh benchmarks/updates.sh        (after sh .ci/setup; about 15 minutes on 2 cores)
# Environment: BUILD (default build), OUT (default doc/updates), RANKS, REPEAT (default 5).
set -eu
cd "$(dirname "$0")/.."
build=${BUILD:-build}
out=${OUT:-doc/updates}
ranks=${RANKS:-"1 3 9 16 32 64"}
repeat=${REPEAT:-5}
matrices=output/benchmarks
mkdir -p "$out" "$matrices"
export OMP_THREAD_LIMIT=1 OPENBLAS_NUM_THREADS=1
# The targets forced beside the default: AVX-512 and AVX2 where this CPU has them.
machine=$(taskset -c 0 "$build/warpchol-kernels" parameters/torus_pull.prm --steps 0 | head -1)
available=$(echo "$machine" | sed -n 's/.*this CPU: \([a-z0-9 ]*\)).*/\1/p')
targets=""
for target in avx512 avx2; do
  case " $available " in *" $target "*) targets="$targets $target" ;; esac
done
# The matrices: the fine torus (10k), SOFA's raptor (18k), the torus at 28k and 60k.
[ -f $matrices/torus_10k.mtx ] || "$build/warpchol-torus-matrix" --dofs 10000 --output $matrices/torus_10k.mtx
[ -f $matrices/raptor.mtx ] || "$build/warpchol-torus-matrix" --mesh meshes/sofa_raptor_19409.vtu --output $matrices/raptor.mtx
[ -f $matrices/torus_28k.mtx ] || "$build/warpchol-torus-matrix" --dofs 28000 --output $matrices/torus_28k.mtx
[ -f $matrices/torus_60k.mtx ] || "$build/warpchol-torus-matrix" --dofs 60000 --output $matrices/torus_60k.mtx
: > "$out/runs.txt.tmp"
for matrix in torus_10k raptor torus_28k torus_60k; do
  for rank in $ranks; do
    echo "== $matrix rank $rank" >&2
    line=$(taskset -c 0 "$build/warpchol-factor" $matrices/$matrix.mtx --method supernodal --ordering metis \
             --changed-fraction 0 --repeat "$repeat" --update-rank "$rank")
    # The update on each target forced, in the same sweep: what an AVX2-only CPU runs.
    forced=""
    for target in $targets; do
      fields=$(WARPCHOL_SIMD_TARGET=$target taskset -c 0 "$build/warpchol-factor" $matrices/$matrix.mtx \
                 --method supernodal --ordering metis --changed-fraction 0 --repeat "$repeat" --update-rank "$rank" |
               tr ' ' '\n' | grep -E '^(update_s|update_vs_cholmod)=' | sed "s/=/_$target=/" | tr '\n' ' ')
      forced="$forced $fields"
    done
    echo "matrix=$matrix $line$forced" >> "$out/runs.txt.tmp"
  done
done
mv "$out/runs.txt.tmp" "$out/runs.txt"
# The table: milliseconds, the flops of the update and of the partial refactorization;
# the update on each target forced, against CHOLMOD in its own run.
awk -v cpu="$(echo "$machine" | sed 's/^machine: \(.*\), SIMD target.*/\1/')" -v targets="$targets" '
  function field(name,   i, kv) { for (i = 1; i <= NF; ++i) { split($i, kv, "="); if (kv[1] == name) return kv[2] } return "" }
  BEGIN {
    n_targets = split(targets, forced, " ")
    header = "| matrix | n | rank | update ms | downdate ms | partial ms | full ms | CHOLMOD updown ms | CHOLMOD downdate ms | update Mflop | partial Mflop | update GF/s | CHOLMOD/update | partial/update | residual |"
    rule = "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    for (t = 1; t <= n_targets; ++t) {
      header = header " " forced[t] " update ms | CHOLMOD/" forced[t] " |"
      rule = rule "---:|---:|"
    }
    print header
    print rule
  }
  {
    printf "| %s | %s | %s | %.3f | %.3f | %.2f | %.1f | %.3f | %.3f | %.1f | %.0f | %s | %s | %s | %s |",
      field("matrix"), field("n"), field("update_rank"), 1e3 * field("update_s"), 1e3 * field("downdate_s"),
      1e3 * field("partial_s"), 1e3 * field("factor_s"), 1e3 * field("cholmod_updown_s"), 1e3 * field("cholmod_downdate_s"),
      1e-6 * field("update_flops"), 1e-6 * field("partial_flops"), field("update_gflops"), field("update_vs_cholmod"),
      field("update_vs_partial"), field("update_residual")
    for (t = 1; t <= n_targets; ++t)
      printf " %.3f | %s |", 1e3 * field("update_s_" forced[t]), field("update_vs_cholmod_" forced[t])
    printf "\n"
    machine = "SIMD target " field("simd") ", updates " field("update_simd") ", dgemm " field("dgemm_gflops") " GFLOP/s (OpenBLAS " field("blas_kernels") "), read " field("read_gbs") " GB/s"
  }
  END {
    print ""
    print "One thread; " cpu ", " machine ". The first columns: the default target; then the update"
    print "with each target forced (WARPCHOL_SIMD_TARGET), each against CHOLMOD timed in the same run."
  }
' "$out/runs.txt" > "$out/table.md.tmp"
mv "$out/table.md.tmp" "$out/table.md"
cat "$out/table.md"
