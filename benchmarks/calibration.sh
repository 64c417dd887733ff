#!/bin/sh
# The WCC threshold across scenes (issues 8 and 18): the trajectory error that fixed
# thresholds and target errors leave on the compact scenes and on the thin bodies (a rod, a
# plate and a vessel, each at a realistic stiffness and overloaded), with the partial
# strategy (the direct solve of the WCC system, whose error is WCC's own). A fixed
# threshold gives errors that differ tenfold from scene to scene; a target error lands
# near itself on the compact ones, and on a thin body in bending, where no threshold holds
# it with few updates, gives up and iterates on the corotational matrix (the summary of
# the run says so; its error is then CG's).
#
#   sh benchmarks/calibration.sh     # about 8 minutes on 2 cores; writes doc/calibration/
#
# Per scene warpchol-threshold-sweep writes doc/calibration/SCENE.{csv,txt,gp,png}; the
# table of the largest trajectory error (max over the steps of the worst vertex's error
# over the largest displacement) per setting and scene goes to doc/calibration/table.md.
set -eu
cd "$(dirname "$0")/.."
build=${BUILD:-build}
out=${OUT:-doc/calibration}
mkdir -p "$out"

thresholds=0.1,0.3,1
target_errors=0.003,0.01,0.03
scenes=${SCENES:-"torus_pull_fine torus_swing liver raptor beam beam_overloaded plate plate_overloaded tube tube_overloaded"}

for scene in $scenes; do
  echo "== $scene"
  "$build/warpchol-threshold-sweep" "parameters/$scene.prm" --threads 1 --strategies none \
    --thresholds "$thresholds" --target-errors "$target_errors" --csv "$out/$scene.csv" > "$out/$scene.txt"
done

# One row per setting, one column per scene, and the spread (largest over smallest).
{
  printf '| setting |'
  for scene in $scenes; do printf ' `%s` |' "$scene"; done
  printf ' largest / smallest |\n|---|'
  for scene in $scenes; do printf -- '---|'; done
  printf -- '---|\n'
  for setting in $(echo "$thresholds" | tr ',' ' ') $(echo "$target_errors" | sed 's/[^,]*/t&/g' | tr ',' ' '); do
    case $setting in
      t*) model=wcc_target; value=${setting#t}; label="target error $value" ;;
      *) model=warp_canceling; value=$setting; label="threshold $value" ;;
    esac
    printf '| %s |' "$label"
    for scene in $scenes; do
      awk -F, -v model="$model" -v value="$value" \
        '$1 == model && $2 + 0 == value + 0 { printf " %.2g |", $15 }' "$out/$scene.csv"
    done
    for scene in $scenes; do
      awk -F, -v model="$model" -v value="$value" '$1 == model && $2 + 0 == value + 0 { print $15 }' "$out/$scene.csv"
    done | awk 'NR == 1 { lo = $1; hi = $1 } { if ($1 < lo) lo = $1; if ($1 > hi) hi = $1 }
                END { printf " %.2g |\n", (lo > 0 ? hi / lo : 0) }'
  done
} > "$out/table.md"
cat "$out/table.md"
