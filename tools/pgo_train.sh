#!/usr/bin/env bash
# PGO training run (cmake/Optimization.cmake, SILOKIT_PGO=ON): runs small
# variants of our scene decks with an instrumented liggghts, which writes
# its branch and call counts (*.gcda) to the profile directory it was built
# with. About a minute on one core.
#
#   bash tools/pgo_train.sh <instrumented liggghts> <work directory>
#
# What the profile should look like is what our decks spend their time on:
# granular pair and wall loops (hooke/stiffness and hertz, tangential
# history, rolling_friction jiang), neighbour lists, nve/sphere, fix clog,
# fix reinject, fix wall/gran/rotating, insertion, rods. Serial runs only:
# the profile is about single-rank code paths (MPI adds communication, which
# the build compiles the same way either way). Sizes and seeds differ from
# those of bench/stock_speed.py, so that the benchmark does not measure the
# training decks themselves.
set -euo pipefail
binary=$(realpath "$1")
work=$2
inputs=$(realpath "$(dirname "$0")/../inputs")
mkdir -p "$work"
cd "$work"

run() {   # run <name> <deck> [-var NAME VALUE ...]
  local name=$1 deck=$2
  shift 2
  mkdir -p "$name"
  echo "pgo_train: $name"
  # screen output only on failure: the training is a build step
  if ! (cd "$name" && "$binary" -in "$inputs/$deck" -log none -var inputs "$inputs" "$@" \
          > screen.txt 2>&1); then
    tail -n 20 "$name/screen.txt"
    echo "pgo_train: $name failed (see $work/$name/screen.txt)" >&2
    exit 1
  fi
}

# the clogging silo (2D, hooke/stiffness, fix clog, fix reinject) until its first arch
run silo2d silo2d/in.silo2d -var quick 1 -var stop_at_first 1 -var seed 15485863
# the rotating-bottom silo, spheres (fix wall/gran/rotating, reinjection)
run silo3d silo3d_rotating/in.silo3d_rotating -var quick 1 -var f 0.32 -var reinject 1 \
    -var discharge_time 0.1 -var seed 15485867
# the same silo with rods (spherocylinders)
run silo3d_rods silo3d_rotating/in.silo3d_rotating -var quick 1 -var shape rod -var f 0.32 \
    -var discharge_time 0.05 -var seed 15485867
# the open 2D pile with rolling resistance: rain, relaxation, a jamming discharge
run pile2d pile2d/in.build -var quick 1 -var model fixed -var seed 32452843
run pile2d pile2d/in.discharge -var quick 1 -var model fixed -var seed 32452843 -var w 2 \
    -var pile pile.restart
echo "pgo_train: done"
