#!/bin/sh
# Re-make every picture that README.md and doc/ show: run each scene whole with
# build/warpchol (each under 10 s on 2 cores; results in output/SCENE/), then draw its PVD
# series with python/render_run.py into doc/pictures/. About a minute; needs the build
# (sh .ci/setup) and xvfb-run (Debian's VTK draws offscreen only with an X display).
#
#   sh doc/pictures/make.sh
set -eu
cd "$(dirname "$0")/../.."

if [ ! -x build/warpchol ]; then
  echo "doc/pictures/make.sh: no build/warpchol: build first (sh .ci/setup)" >&2
  exit 2
fi
# One X display for all the pictures.
if [ -z "${DISPLAY:-}" ]; then
  if ! command -v xvfb-run > /dev/null; then
    echo "doc/pictures/make.sh: no X display and no xvfb-run (Debian package xvfb)" >&2
    exit 2
  fi
  exec xvfb-run -a sh "$0" "$@"
fi

pictures=doc/pictures
mkdir -p output/pictures

# run SCENE: the scene's whole run, its summary kept in output/pictures/SCENE.txt.
run() {
  echo "run $1"
  build/warpchol "parameters/$1.prm" > "output/pictures/$1.txt"
}

# draw SCENE [OPTIONS]: a contact sheet of six frames (or what OPTIONS say) of its run,
# frames of 640 x 480 pixels.
draw() {
  scene=$1
  shift
  python/render_run.py "output/$scene/$scene.pvd" --out "$pictures" --size 640x480 "$@" > /dev/null
}

# The default scene: the README's picture (three frames in a row) and its stress at step 50.
run torus_pull
draw torus_pull --no-frames --sheet 3
draw torus_pull --field stress --prm parameters/torus_pull.prm --steps 50 --sheet 0

# Several bodies: stiffness warping, WCC at threshold 1, exact corotation (doc/simulation.md).
run three_tori
draw three_tori --no-frames --field rerotated --azimuth 0 --elevation 30

# Where WCC re-rotates: SOFA's raptor and the plate (doc/strategies.md).
run raptor
draw raptor --no-frames --field rerotated
run plate
draw plate --no-frames --field rerotated

# Cuts, grasps and material changes (doc/surgery.md).
for scene in liver_cut torus_cut grasp_release torus_cauterize flap_incision; do
  run $scene
  draw $scene --no-frames
done

# Contact (doc/contact.md): the palpation (contact force; the table and the probe drawn
# grey) and the retraction (the capsule under the tongue).
run liver_palpation
draw liver_palpation --no-frames --field contact_force --steps 0,30,50,55,70,95
run flap_retraction
draw flap_retraction --no-frames --steps 100,140,160,180,200,220 --view=-y --up z --elevation 25 --azimuth 20

ls "$pictures"/*.png
