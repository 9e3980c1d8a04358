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

run() {   # run <name> <deck, under inputs/ or absolute> [-var NAME VALUE ...]
  local name=$1 deck=$2
  shift 2
  [[ $deck = /* ]] || deck=$inputs/$deck
  mkdir -p "$name"
  echo "pgo_train: $name"
  # screen output only on failure: the training is a build step
  if ! (cd "$name" && "$binary" -in "$deck" -log none -var inputs "$inputs" "$@" \
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
# stock LIGGGHTS as its users run it: Hertz pair and primitive walls, spheres
# settling in a cylinder (bench/stock_speed.py's stock deck times a box with
# other sizes, materials and seeds). Without it the Hertz model is code the
# profile never saw, compiled as without PGO (-fprofile-partial-training).
mkdir -p hertz
cat > hertz/in.hertz <<'DECK'
atom_style granular
atom_modify map array
boundary m m m
newton off
communicate single vel yes
units si
region reg block -0.035 0.035 -0.035 0.035 0. 0.12 units box
create_box 1 reg
neighbor 0.0016 bin
neigh_modify delay 0
fix m1 all property/global youngsModulus peratomtype 1.e7
fix m2 all property/global poissonsRatio peratomtype 0.3
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5
fix m4 all property/global coefficientFriction peratomtypepair 1 0.4
pair_style gran model hertz tangential history
pair_coeff * *
timestep 0.00001
fix cyl all wall/gran model hertz tangential history primitive type 1 zcylinder 0.034 0. 0.
fix floor all wall/gran model hertz tangential history primitive type 1 zplane 0.0
fix roof all wall/gran model hertz tangential history primitive type 1 zplane 0.12
fix gravi all gravity 9.81 vector 0.0 0.0 -1.0
fix pts1 all particletemplate/sphere 49979687 atom_type 1 density constant 2000 radius constant 0.002
fix pts2 all particletemplate/sphere 49979693 atom_type 1 density constant 2000 radius constant 0.0024
fix pdd1 all particledistribution/discrete 67867967 2 pts1 0.6 pts2 0.4
region ins cylinder z 0. 0. 0.032 0.01 0.118 units box
fix ins all insert/pack seed 67867979 distributiontemplate pdd1 maxattempt 100 insert_every once &
    overlapcheck yes all_in yes vel constant 0. 0. -0.5 region ins volumefraction_region 0.25
fix integr all nve/sphere
thermo 2000
thermo_style custom step atoms ke
run 20000
DECK
run hertz "$PWD/hertz/in.hertz"
# the open 2D pile with rolling resistance: rain, relaxation, a jamming discharge
run pile2d pile2d/in.build -var quick 1 -var model fixed -var seed 32452843
run pile2d pile2d/in.discharge -var quick 1 -var model fixed -var seed 32452843 -var w 2 \
    -var pile pile.restart
echo "pgo_train: done"
