#!/bin/sh
# Fast on every machine and every mesh (issue 26): per SIMD target the CPU has (avx512,
# avx2, forced by WARPCHOL_SIMD_TARGET), the element kernels (warpchol-kernels: ns per tet,
# every target side by side) and the study's sweep reduced to what the goals read (the
# exact path, the partial strategy and auto at thresholds 0.3, 1 and inf), on the study's
# scenes and SOFA's real meshes (the liver, the raptor, the 21:1 PDMS cylinder, realistic
# and overloaded). Writes doc/targets/: kernels-SCENE.txt, SCENE-TARGET-tN.txt and .csv,
# and summary.md (per scene, target and core count: exact s/step, the best run at <= 1 %
# error, auto's best, their speed-ups, errors, CG iterations and the GB/s of CG).
#   sh benchmarks/targets.sh        (after sh .ci/setup; about an hour on 2 cores)
# Environment: BUILD (default build), OUT (default doc/targets), THREADS (default "1 2"),
# TARGETS (default: avx512 and avx2 where the CPU has them), SCENES (default: below).
set -eu
cd "$(dirname "$0")/.."
build=${BUILD:-build}
out=${OUT:-doc/targets}
thread_counts=${THREADS:-"1 2"}
scenes=${SCENES:-"torus_pull_fine torus_pull_60k liver raptor beam beam_overloaded plate plate_overloaded tube tube_overloaded cylinder cylinder_overloaded"}
export OMP_THREAD_LIMIT=1 OPENBLAS_NUM_THREADS=1
mkdir -p "$out"

# The targets: those asked for that this CPU runs (the kernels program lists them).
machine=$(taskset -c 0 "$build/warpchol-kernels" parameters/torus_pull.prm --steps 0 | head -1)
available=$(echo "$machine" | sed -n 's/.*this CPU: \([a-z0-9 ]*\)).*/\1/p')
targets=""
for target in ${TARGETS:-avx512 avx2}; do
  case " $available " in *" $target "*) targets="$targets $target" ;; esac
done

summary="$out/summary.md"
{
  echo "# Per SIMD target: seconds per step at <= 1 % trajectory error"
  echo
  echo "Written by \`sh benchmarks/targets.sh\`. exact: the corotational model assembled and"
  echo "factored every step; best: the fastest run at <= 1 % max trajectory error (partial at"
  echo "thresholds 0.3, 1, inf; auto at 0.3, 1, inf); auto: auto's fastest there. Speed-ups"
  echo "against exact in the same sweep, on the same target."
  echo
  echo "$machine"
  echo
  echo "| scene | target | cores | exact s/step | best at <= 1 % | auto |"
  echo "|---|---|---|---|---|---|"
} > "$summary.tmp"

for scene in $scenes; do
  echo "== kernels: $scene"
  taskset -c 0 "$build/warpchol-kernels" "parameters/$scene.prm" --targets "$(echo $targets | tr ' ' ',')" \
    > "$out/kernels-$scene.txt.tmp"
  mv "$out/kernels-$scene.txt.tmp" "$out/kernels-$scene.txt"
  cat "$out/kernels-$scene.txt"
  for target in $targets; do
    for threads in $thread_counts; do
      cores=$(seq -s, 0 $((threads - 1)))
      echo "== $scene, $target, $threads thread(s)"
      table="$out/$scene-$target-t$threads.txt"
      WARPCHOL_SIMD_TARGET=$target taskset -c "$cores" "$build/warpchol-threshold-sweep" "parameters/$scene.prm" \
        --threads "$threads" --thresholds 0.3,1,inf --strategies auto --strategy-thresholds 0.3,1,inf \
        --csv "$out/$scene-$target-t$threads.csv" > "$table.tmp"
      mv "$table.tmp" "$table"
      grep -E "^(exact|best|auto) " "$table"
      exact=$(sed -n 's/^exact (corotational): \([^ ]*\) s\/step/\1/p' "$table")
      best=$(sed -n 's/^best at <= 1 % error: //p' "$table")
      auto=$(sed -n 's/^auto at <= 1 % error: //p' "$table")
      echo "| $scene | $target | $threads | $exact | $best | $auto |" >> "$summary.tmp"
    done
  done
done
mv "$summary.tmp" "$summary"
cat "$summary"
