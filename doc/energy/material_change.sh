#!/bin/sh
# The energy logs of issue 29's scene: parameters/torus_cut.prm with its cut switched off,
# 30 steps, the elements in a sphere (centre 0, 0, -0.4, radius 0.1) stiffened 1e8 times at
# 0.05 s, with Material change/Stress = continuous and = reset, the energy growth limit at
# its default (10). Writes doc/energy/material_change.md (the tables and the summaries'
# energy lines); the runs' logs and summaries stay in output/energy/.
#   sh doc/energy/material_change.sh      (after sh .ci/setup; about a minute on 2 cores)
# Environment: BUILD (default build), WORK (default output/energy), OUT (default doc/energy).
set -eu
cd "$(dirname "$0")/../.."
build=${BUILD:-build}
work=${WORK:-output/energy}
out=${OUT:-doc/energy}
mkdir -p "$work" "$out"
export OMP_THREAD_LIMIT=1 OPENBLAS_NUM_THREADS=1
# From $work, the repository's root.
root=$(echo "$work" | sed 's|[^/][^/]*|..|g')

for stress in continuous reset; do
  name=material_change_$stress
  cat > "$work/$name.prm" <<PRM
include $root/parameters/torus_cut.prm
subsection Time stepping
  set Number of steps = 30
end
subsection Cut
  set Duration = 0
end
subsection Material change
  set Region           = sphere
  set Sphere center    = 0, 0, -0.4
  set Sphere radius    = 0.1
  set Time             = 0.05
  set Stiffness factor = 1e8
  set Stress           = $stress
end
subsection Output
  set Directory     = $work
  set VTU interval  = 0
  set Write log     = true
  set Print timings = false
  set Progress      = off
end
PRM
  echo "== $name"
  status=0
  "$build/warpchol" "$work/$name.prm" > "$work/$name.txt" 2>&1 || status=$?
  echo "exit status $status" >> "$work/$name.txt"
  cat "$work/$name.txt"
done

# A table of the energy columns of a log, picked by name.
table() {
  awk -F, '
    NR == 1 { for (i = 1; i <= NF; ++i) column[$i] = i
              n = split("step time kinetic_energy elastic_energy potential_energy external_work change_energy total_energy energy_ratio", names, " ")
              line = "|"; rule = "|"
              for (k = 1; k <= n; ++k) { line = line " " names[k] " |"; rule = rule "---|" }
              print line; print rule; next }
    { line = "|"; for (k = 1; k <= n; ++k) line = line " " $(column[names[k]]) " |"; print line }' "$1"
}

{
  echo "# A material change that stiffens a strained region: the energy logs (issue 29)"
  echo
  echo "\`parameters/torus_cut.prm\` with its cut switched off (\`Cut/Duration = 0\`), 30 steps of"
  echo "0.01 s, WCC (\`Rerotation threshold = inf\`, \`Strategy = auto\`), gravity; at 0.05 s (the start"
  echo "of step 6) the elements in a sphere (centre 0, 0, -0.4, radius 0.1) become 1e8 times"
  echo "stiffer. \`Time stepping/Energy growth limit\` at its default, 10. Before issue 29 the run"
  echo "stopped at step 6: \`the energy of warp_canceling grew to 5.36e+05 J (start 0 J, work of"
  echo "the external loads 0.166 J), over Time stepping/Energy growth limit = 10 times what was"
  echo "put in: the simulation diverged\`: the balance did not count what the change put in."
  echo
  echo "Now the balance counts it: \`change_energy\` is the energy the changes put in or took out"
  echo "so far (here the changed elements' elastic energy after the change minus before it, at"
  echo "step 6), and \`energy_ratio\` = held / (initial + work of the loads + change_energy)."
  echo "Energies in J; \`potential_energy\` is gravity's (negative: the body sags)."
  echo
  echo "With \`continuous\` the changed elements keep their stress: their elastic energy is"
  echo "divided by 1e8 (the change takes it out, a few tenths of a microjoule), the stiffened"
  echo "region holds the shape it had and resists only further deformation. With \`reset\`"
  echo "they keep their rest shape: at the positions of step 5 their energy jumps by the change's"
  echo "energy, the step then relaxes part of it, and the region springs back over the next"
  echo "0.2 s (Rayleigh's stiffness damping, 0.1 s); counted, the jump is no divergence."
  echo
  echo "Reproduce: \`sh doc/energy/material_change.sh\` (scenes and logs in \`$work/\`)."
  for stress in continuous reset; do
    name=material_change_$stress
    echo
    echo "## \`Material change/Stress = $stress\`"
    echo
    awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) column[$i] = i; next }
      { elastic[$1] = $(column["elastic_energy"]); change = $(column["change_energy"])
        ratio = $(column["energy_ratio"]); if (ratio > largest) largest = ratio }
      END { printf "Across the change the elastic energy goes from %.3g J (step 5) to %.3g J (step 6);", elastic[5], elastic[6]
            printf " the change put in %.3g J; the largest energy ratio is %.3g, the limit 10.\n\n", change, largest }' \
      "$work/$name/log.csv"
    echo "Summary (energy lines):"
    echo
    grep -E "steps:|energy at the end|energy of the changes|warning|error|exit status" "$work/$name.txt" | sed 's/^ */    /'
    echo
    table "$work/$name/log.csv"
  done
} > "$out/material_change.md"
echo "wrote $out/material_change.md"
