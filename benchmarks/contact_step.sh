#!/bin/sh
# A contact step against the contact-free step (issue 37's goal: detection + W +
# Gauss-Seidel + correction <= 50 % of the rest of the step), averaged over a contact
# scene's run on one core:
#   sh benchmarks/contact_step.sh        (liver_palpation, 3 runs, about 15 s)
# Environment: BUILD (default build), SCENE (default liver_palpation), RUNS (default 3),
# CORE (default 1), REFINEMENTS (default: the scene's Mesh/Refinements; 0 runs SOFA's liver
# as SOFA ships it, 596 tets, about a quarter of the rows). Per run: the contact stages' ms
# per step (the summary's stage table), the rest of the step's, their ratio, and the rows of
# H per step (3 per contact, log.csv); first the machine (CPU, SIMD targets, dgemm, read
# bandwidth), last the ratio's median and range over the runs.
set -eu
cd "$(dirname "$0")/.."
build=${BUILD:-build}
scene=${SCENE:-liver_palpation}
runs=${RUNS:-3}
core=${CORE:-1}
summary=$(mktemp)
trap 'rm -f "$summary"' EXIT
if [ -n "${REFINEMENTS:-}" ]; then
  # The scene with its mesh refined REFINEMENTS times, beside it (its paths are relative).
  case $REFINEMENTS in
    *[!0-9]*) echo "contact_step.sh: REFINEMENTS=$REFINEMENTS is not a number of refinements" >&2; exit 1 ;;
  esac
  if ! grep -q '^ *set Refinements *=' "parameters/$scene.prm"; then
    echo "contact_step.sh: parameters/$scene.prm sets no Mesh/Refinements for REFINEMENTS to replace" >&2
    exit 1
  fi
  variant="${scene}_refined_$REFINEMENTS"
  sed "s/^\( *set Refinements *=\).*/\1 $REFINEMENTS/" "parameters/$scene.prm" > "parameters/$variant.prm"
  trap 'rm -f "$summary" "parameters/$variant.prm"' EXIT
  scene=$variant
fi
taskset -c "$core" "$build/warpchol-kernels" parameters/torus_pull.prm --steps 0 | head -1
echo "$scene, one core (taskset -c $core), $runs runs"
ratios=""
for run in $(seq "$runs"); do
  OMP_THREAD_LIMIT=1 OPENBLAS_NUM_THREADS=1 taskset -c "$core" "$build/warpchol" "parameters/$scene.prm" > "$summary"
  rows=$(awk -F, 'NR == 1 { for (k = 1; k <= NF; ++k) if ($k == "contacts") column = k; next }
                  { sum += 3 * $column; ++steps } END { printf "%.0f", sum / steps }' "output/$scene/log.csv")
  line=$(awk -v run="$run" -v rows="$rows" '
    $1 == "contact" && $2 == "detection"    { detection = $4 }
    $1 == "contact" && $2 == "compliance"   { compliance = $4 }
    $1 == "contact" && $2 == "Gauss-Seidel" { gauss_seidel = $4 }
    $1 == "contact" && $2 == "correction"   { correction = $4 }
    $1 == "time" && $2 == "steps" && NF >= 5 { step = $4 }
    END {
      contact = detection + compliance + gauss_seidel + correction
      free = step - contact
      printf "run %d: %d rows per step; contact %.2f ms per step (detection %.2f, W %.2f, Gauss-Seidel %.2f, correction %.2f), contact-free %.2f ms: ratio %.2f\n",
             run, rows, 1e3 * contact, 1e3 * detection, 1e3 * compliance, 1e3 * gauss_seidel, 1e3 * correction, 1e3 * free, contact / free
    }' "$summary")
  echo "$line"
  ratios="$ratios ${line##* }"
done
# On a shared machine the runs spread: their median and range.
echo "$ratios" | tr ' ' '\n' | grep . | sort -n | awk '{ r[NR] = $1 }
  END { m = NR % 2 ? r[(NR + 1) / 2] : (r[NR / 2] + r[NR / 2 + 1]) / 2
        printf "ratio over the %d runs: median %.2f, range %.2f-%.2f\n", NR, m, r[1], r[NR] }'
