#!/bin/sh
# auto against the exact path where no fast strategy pays (issue 36): overloaded slender
# bodies, generated (solid rods, tubes and square bars of several aspect ratios, a thin
# plate and a torus, at Young's moduli far too low to carry their weight) and real (SOFA's
# 21:1 PDMS cylinder of meshes/; SOFA's cylinder, livers and low-resolution torus of
# ../shared/data/meshes, which the repository does not hold, in their files' numbering,
# where that folder exists), and the study's
# overloaded bodies (parameters/*_overloaded.prm). Each scene runs with WCC's exact step
# (threshold 0: what auto's own exact steps cost) and with auto at thresholds 0.3, 1 and
# inf, each with the exact path (the corotational model) beside it, step by step in the
# same process (Output/Compare with corotational): a slower or faster spell of the machine
# slows both alike. It prints per scene the exact path's seconds per step and each run's
# speed-up over the exact path beside it, as ranges over REPEAT rounds of all scenes, in a
# Markdown table (OUT/table.md, copied to TABLE; the runs' summaries and parameter files in
# OUT/runs/, the scenes' in OUT/scenes/).
#   sh benchmarks/auto_vs_exact.sh   (after sh .ci/setup; about 35 minutes with REPEAT=3)
# Environment: BUILD (default build), OUT (default output/auto_vs_exact), TABLE (default
# doc/auto_vs_exact/table.md), REPEAT (default
# 3), CORE (the core to pin to, default 0), SCENES (default: all below), SHARED (default
# ../shared/data: the real meshes outside the repository).
set -eu
cd "$(dirname "$0")/.."
root=$(pwd)
build=${BUILD:-build}
out=${OUT:-output/auto_vs_exact}
repeat=${REPEAT:-3}
case $repeat in
  '' | *[!0-9]* | 0) echo "auto_vs_exact.sh: REPEAT=$repeat is not a number of rounds (1 or more)" >&2; exit 1 ;;
esac
core=${CORE:-0}
shared=${SHARED:-../shared/data}
mkdir -p "$out/scenes"
out=$(cd "$out" && pwd)
# As every comparison of this project: one BLAS thread, no OpenMP regions of CHOLMOD's.
export OMP_THREAD_LIMIT=1 OPENBLAS_NUM_THREADS=1

# What every scene shares: the study's time stepping, WCC auto with CG to 1e-3 on the
# corotational matrix, gravity along -y.
common() {
  cat <<EOF
subsection Material
  set Young's modulus = $1
  set Poisson's ratio = 0.45
  set Density         = 1000
end
subsection Time stepping
  set Time step          = 0.01
  set Number of steps    = 100
  set Rayleigh mass      = 0.1
  set Rayleigh stiffness = 0.01
end
subsection Model
  set Type             = warp_canceling
  set Rerotation threshold = 1
  set Strategy         = auto
  set CG tolerance     = 1e-3
end
subsection Solver
  set Ordering = metis
  set Method   = supernodal
  set Preconditioner precision = half
end
subsection Gravity
  set Acceleration = 0, -9.81, 0
end
subsection Output
  set VTU interval = 0
  set Write log    = false
end
EOF
}

# Held where the coordinate along axis $1 (x or z) is <= 0, (top) where y >= 0.5, or in
# the box LOWER:UPPER ($1 = "box:x0, y0, z0:x1, y1, z1").
held_at() {
  lower="-9, -9, -9"
  case $1 in
    x) upper="1e-6, 9, 9" ;;
    z) upper="9, 9, 1e-6" ;;
    top) lower="-9, 0.5, -9" upper="9, 9, 9" ;;
    box:*) lower=$(echo "$1" | cut -d: -f2) upper=$(echo "$1" | cut -d: -f3) ;;
  esac
  printf 'subsection Fixed vertices\n  set Region           = box\n  set Box lower corner = %s\n  set Box upper corner = %s\nend\n' "$lower" "$upper"
}

# rod ASPECT E: deal.II's cylinder, radius 2.5 mm, ASPECT diameters long along x, held at x = 0.
rod() {
  {
    printf 'subsection Mesh\n  set Source = cylinder\n  set Cylinder radius = 0.0025\n'
    printf '  set Cylinder length = %s\n  set Cylinder axial cells = %s\n  set Cylinder refinements = 1\nend\n' \
      "$(echo "0.005 * $1" | bc -l)" $(($1 * 4 / 5))
    common "$2"
    held_at x
  } > "$out/scenes/rod$1_E$2.prm"
}

# tube ASPECT E: deal.II's cylinder shell (radii 3 and 4 mm), ASPECT outer diameters long
# along z, held at z = 0, hanging sideways.
tube() {
  {
    printf 'subsection Mesh\n  set Source = tube\n  set Tube inner radius = 0.003\n  set Tube outer radius = 0.004\n'
    printf '  set Tube length = %s\n  set Tube circumferential cells = 16\n  set Tube axial cells = %s\nend\n' \
      "$(echo "0.008 * $1" | bc -l)" $(($1 * 5 / 2))
    common "$2"
    held_at z
  } > "$out/scenes/tube$1_E$2.prm"
}

# bar ASPECT E [CELLS]: deal.II's box, a 5 mm square section ASPECT times as long along x,
# held at x = 0; CELLS across the section (3: named barASPECT_EE, else barASPECT_CELLS_EE),
# CELLS per section width along x.
bar() {
  cells=${3:-3}
  name="bar$1_E$2"
  [ "$cells" = 3 ] || name="bar$1_${cells}_E$2"
  {
    printf 'subsection Mesh\n  set Source = box\n  set Box lower corner = 0, 0, 0\n'
    printf '  set Box upper corner = %s, 0.005, 0.005\n  set Box subdivisions = %s, %s, %s\nend\n' \
      "$(echo "0.005 * $1" | bc -l)" $(($1 * cells)) "$cells" "$cells"
    common "$2"
    held_at x
  } > "$out/scenes/$name.prm"
}

# plate SIDE E: deal.II's box, a square plate SIDE cm wide and 5 mm thick (one cell), held
# along its edge at x = 0, sagging.
plate() {
  {
    printf 'subsection Mesh\n  set Source = box\n  set Box lower corner = 0, 0, 0\n'
    printf '  set Box upper corner = %s, 0.005, %s\n  set Box subdivisions = %s, 1, %s\nend\n' \
      "$(echo "0.01 * $1" | bc -l)" "$(echo "0.01 * $1" | bc -l)" $(($1 * 2)) $(($1 * 2))
    common "$2"
    held_at x
  } > "$out/scenes/plate$1_E$2.prm"
}

# torus E: deal.II's torus (radii 0.3 and 0.1 m), held by a patch of its side (x >= 0.35).
torus() {
  {
    printf 'subsection Mesh\n  set Source = torus\n  set Torus major radius = 0.3\n  set Torus minor radius = 0.1\n'
    printf '  set Torus toroidal cells = 16\n  set Torus refinements = 1\nend\n'
    common "$1"
    held_at "box:0.35, -9, -9:9, 9, 9"
  } > "$out/scenes/torus_E$1.prm"
}

# mesh NAME FILE E WHERE [MASS]: a mesh file as it is, in its numbering, held as held_at
# WHERE says; with MASS, that total mass (kg) instead of the density.
mesh() {
  {
    printf 'subsection Mesh\n  set Source = file\n  set File   = %s\nend\n' "$2"
    if [ -n "${5:-}" ]; then
      common "$3" | sed "s/  set Density  *= 1000/  set Total mass      = $5/"
    else
      common "$3"
    fi
    held_at "$4"
  } > "$out/scenes/$1.prm"
}

rod 10 1e3
rod 20 1e3
rod 40 1e3
rod 60 1e3
rod 20 3e2
rod 40 3e2
rod 40 1e4
tube 8 1e3
tube 15 1e3
bar 30 1e3
bar 50 1e3 2
tube 25 3e2
plate 20 3e2
torus 3e2
# SOFA's PDMS cylinder (meshes/README.md): 21:1, radius 4.25 mm, along z from z = 0; at
# E 10 kPa it is parameters/cylinder_overloaded.prm.
mesh pdms_cylinder_E1e3 "$root/meshes/sofa_cylinder_pdms_12724.vtk" 1e3 z
# SOFA's share/mesh/cylinder.msh (radius 0.25, 1 long along z from z = 0: 2:1) and liver2.msh.
[ -f "$shared/meshes/sofa_cylinder.msh" ] &&
  mesh sofa_cylinder_E3e2 "$(cd "$shared/meshes" && pwd)/sofa_cylinder.msh" 3e2 z
[ -f "$shared/meshes/sofa_liver2.msh" ] &&
  mesh sofa_liver2_E30 "$(cd "$shared/meshes" && pwd)/sofa_liver2.msh" 30 top
# SOFA's classic liver (E 30 Pa, 1 kg, held at its top) and its low-resolution torus (the
# torus fall benchmark's E 50 Pa and 20 kg, held by a patch of its side), the smallest bodies.
[ -f "$shared/meshes/sofa_liver.v22.msh" ] &&
  mesh sofa_liver_E30 "$(cd "$shared/meshes" && pwd)/sofa_liver.v22.msh" 30 "box:-99, 4.7, -99:99, 99, 99" 1
[ -f "$shared/meshes/sofa_torus_low_res.v22.msh" ] &&
  mesh sofa_torus_E50 "$(cd "$shared/meshes" && pwd)/sofa_torus_low_res.v22.msh" 50 "box:2, -99, -99:99, 99, 99" 20

# The study's overloaded bodies and the PDMS cylinder's, as parameters/ has them.
scenes=${SCENES:-"$(cd "$out/scenes" && ls *.prm | sed 's/\.prm$//' | tr '\n' ' ')beam_overloaded plate_overloaded tube_overloaded cylinder_overloaded"}

# run SCENE COLUMN STRATEGY THRESHOLD: the scene with WCC's STRATEGY at THRESHOLD and the
# exact path beside it, step by step in the same process (Output/Compare with corotational):
# the "reference run" of its summary over its "time steps", each in seconds per step.
run() {
  prm="$out/scenes/$1.prm"
  [ -f "$prm" ] || prm="$root/parameters/$1.prm"
  cat > "$out/runs/$1-$2.prm" <<EOF
include $prm
subsection Model
  set Type             = warp_canceling
  set Strategy         = $3
  set Rerotation threshold = $4
  set Target error     = 0
  set Iterate on       = corotational
end
subsection Solver
  set Threads = 1
end
subsection Output
  set Directory                 = $out/runs
  set VTU interval              = 0
  set Write log                 = false
  set Compare with corotational = true
end
EOF
  summary="$out/runs/$1-$2-$round.txt"
  taskset -c "$core" "$build/warpchol" "$out/runs/$1-$2.prm" > "$summary"
  # One line: scene, column, the exact path's s/step over the run's (its speed-up), the
  # exact path's s/step, tets.
  awk -v scene="$1" -v column="$2" '
    /^ *mesh: / { for (i = 1; i < NF; ++i) if ($(i + 1) ~ /^tets/) tets = $i }
    /^ *reference run/ { exact = $(NF - 2) }
    /^ *time steps/ { steps = $(NF - 2) }
    END { print scene, column, exact / steps, exact, tets }' "$summary" >> "$ratios"
}

mkdir -p "$out/runs"
ratios="$out/ratios.txt"
: > "$ratios"
round=1
while [ "$round" -le "$repeat" ]; do
  for scene in $scenes; do
    echo "== $scene, round $round of $repeat" >&2
    run "$scene" wcc0 partial 0
    for threshold in 0.3 1 inf; do
      run "$scene" "auto$threshold" auto "$threshold"
    done
  done
  round=$((round + 1))
done

machine=$(taskset -c "$core" "$build/warpchol-kernels" parameters/torus_pull.prm --steps 0 | head -1)
{
  echo "$machine; one thread, $repeat rounds (ranges over them)"
  echo
  echo "| scene | tets | exact s/step | WCC exact step | auto 0.3 | auto 1 | auto inf |"
  echo "|---|---:|---:|---:|---:|---:|---:|"
  for scene in $scenes; do
    awk -v scene="$scene" '
      function add(column, value) {
        if (!(column in low) || value < low[column]) low[column] = value
        if (!(column in high) || value > high[column]) high[column] = value
      }
      function range(column, format, unit,   text) {
        if (!(column in low)) return "-"
        text = sprintf(format, low[column])
        if (sprintf(format, high[column]) != text) text = text "-" sprintf(format, high[column])
        return text unit
      }
      $1 == scene { add($2, $3); add("exact", $4); tets = $5 }
      END {
        printf "| %s | %s | %s | %s | %s | %s | %s |\n", scene, tets, range("exact", "%.4f", ""),
               range("wcc0", "%.2f", "x"), range("auto0.3", "%.2f", "x"), range("auto1", "%.2f", "x"),
               range("autoinf", "%.2f", "x")
      }' "$ratios"
  done
} > "$out/table.md"
table=${TABLE:-doc/auto_vs_exact/table.md}
mkdir -p "$(dirname "$table")"
cp "$out/table.md" "$table"
cat "$table"
