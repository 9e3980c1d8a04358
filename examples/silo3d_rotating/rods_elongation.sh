#!/bin/bash
# The rods' elongation campaign (Pongó et al. 2022, Figs. 3a and 3b;
# doc/silo3d_rotating.md, "Elongation"): L/d = 4.0 and 2.5 at D = 60 mm,
# f = 0, 0.32 and 1.28 Hz, two packings each. The runs of Fig. 3a (f = 0
# and 0.32 Hz) last 8 s, so that their ratio can be taken over 4-8 s: the
# rods' flow at rest still rises at 4 s (at L/d = 2.5 and 3.3; the issue's
# rule, doc/campaigns/silo3d_rotating.md "Which window"); their orifice
# series cover 2-8 s, so that 2-4 s can be compared. The 1.28 Hz runs
# (Fig. 3b) last 4 s. It runs rods_fig2c.sh once per stage, in the order that gives
# Fig. 3a first and L/d = 4.0 before 2.5:
#
#   1. 4.0, first packing, f = 0 and 0.32     2. 4.0, second packing, same
#   3. 2.5, first packing, f = 0 and 0.32     4. 2.5, second packing, same
#   5. 4.0, both packings, f = 1.28           6. 2.5, both packings, f = 1.28
#   7. 3.3, first and second packings, f = 0.32, 8 s: the 3.3 point over
#      4-8 s (its 8 s runs at rest are earlier campaigns': silo3d_rods_drop_8s
#      for the first packing, silo3d_rods_fig2c for the second); its packings
#      are the Fig. 2c campaign's, carried in carry/silo3d_rods_elongation_L3.3
#   8. spheres (L/d = 1), three packings, f = 0, 0.32 and 1.28, 2 s each
#      (SPHERES_PROTOCOL): the runs of the cross-host bench's LIGGGHTS side
#      (doc/data/silo3d_cross_host, the same deck, seeds and settling), run
#      again with dumps for the orifice averages at L/d = 1, which the bench
#      did not keep; store silo3d_rods_elongation_spheres
#
# A finished 4 s run of stages 1-4 is made 8 s long from its last
# checkpoint (run.sh) when one is in its directory; the log says how the
# runs finished before that rule got theirs back from carry/ in the history.
#
#   bash examples/silo3d_rotating/rods_elongation.sh run  RUN_DIR
#       restores what earlier machines carried and runs the stages in order
#       (each stage's settling and runs resume where they stopped)
#   bash examples/silo3d_rotating/rods_elongation.sh keep RUN_DIR
#       every hour and before the machine goes (the runs may go on; a
#       session can end without warning): analyses and archives
#       the finished runs into doc/data/silo3d_rods_elongation_L<aspect>
#       and carries the rest into carry/; then commit both
#
# Settlings write a checkpoint every 0.25 s, so that one cut short by the
# machine's end is carried too (a settling of 22 500 rods takes hours).
#
# Environment (defaults in brackets):
#   STAGES   which stages, in which order      ["1 2 3 4 5 6 7 8"]
#   JOBS     runs at once within a stage        [1]
#   STORES   the folder of the stores           [doc/data]
#   PROTOCOL "f discharge transient" triples    ["0 8 2  0.32 8 2  1.28 4 2"]
#            (the transient is where the orifice series starts; the
#            analysis of Fig. 3 takes its own windows from discharge.txt)
#   SPHERES_PROTOCOL  the same for stage 8  ["0 2 0.5  0.32 2 0.5  1.28 2 0.5"]
#   DECK_VARS, CHECKPOINT go to run.sh (e.g. DECK_VARS="quick 1" for a test;
#            stage 8 runs without checkpoints, below)
#   SILOKIT_LIGGGHTS, SILOKIT_INPUTS: a frozen binary and decks for a
#            campaign that outlasts the tree's changes (run.sh)
#   GLIBC_TUNABLES  [glibc.malloc.hugetlb=1]: malloc on transparent huge
#            pages; the rods end at the same positions to the bit and a step
#            of 22 500 rods takes 0.85 times as long
#            (doc/accuracy_cost_spherocylinder.md, L/d = 4.0 per rod-step)
set -euo pipefail
export GLIBC_TUNABLES="${GLIBC_TUNABLES:-glibc.malloc.hugetlb=1}"
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
ACTION="${1:-}"
RUN_DIR="${2:-}"
[ -n "$RUN_DIR" ] && { [ "$ACTION" = run ] || [ "$ACTION" = keep ]; } || {
  echo "usage: bash examples/silo3d_rotating/rods_elongation.sh run|keep RUN_DIR" >&2; exit 2; }
STAGES="${STAGES:-1 2 3 4 5 6 7 8}"
FIRST=32452843 SECOND=15485863 THIRD=49979687
# Fig. 3a's runs 8 s, Fig. 3b's 4 s; every orifice series from 2 s on
PROTOCOL="${PROTOCOL:-0 8 2  0.32 8 2  1.28 4 2}"
# the spheres' runs as the cross-host bench's: 2 s, Q over 0.5-2 s
SPHERES_PROTOCOL="${SPHERES_PROTOCOL:-0 2 0.5  0.32 2 0.5  1.28 2 0.5}"
STORES="${STORES:-$ROOT/doc/data}"

stage() {   # stage N -> "aspect seeds frequencies"
  case "$1" in
    1) echo "4.0|$FIRST|0 0.32" ;;  2) echo "4.0|$SECOND|0 0.32" ;;
    3) echo "2.5|$FIRST|0 0.32" ;;  4) echo "2.5|$SECOND|0 0.32" ;;
    5) echo "4.0|$FIRST $SECOND|1.28" ;;  6) echo "2.5|$FIRST $SECOND|1.28" ;;
    7) echo "3.3|$FIRST $SECOND|0.32" ;;
    8) echo "spheres|$FIRST $SECOND $THIRD|0 0.32 1.28" ;;
    *) echo "rods_elongation.sh: STAGES: no stage '$1' (1-8)" >&2; return 2 ;;
  esac
}
# The page uses Q and the orifice averages (the paper's Figs. 2b, 2d, 3
# and 8), not maps: the archives keep no fields.npz, so that the runs fit
# doc/data's 30 MB (about 0.1 MB each). The spheres settle and discharge
# each in one run, as the bench's did, so that their packings and
# trajectories are the bench's: a run cut into pieces by checkpoints is
# another trajectory at round-off (a discharge with checkpoints every
# 0.25 s parts from the bench's at 0.3 s). A settling or a 2 s run takes
# minutes: one cut short runs again.
campaign() {   # campaign ACTION ASPECT SEEDS FS
  local shape=rod aspect="$2" protocol="$PROTOCOL" settle_checkpoint=0.25 name="L$2"
  local checkpoint="${CHECKPOINT:-0.25}"
  if [ "$2" = spheres ]; then
    shape=sphere aspect="" protocol="$SPHERES_PROTOCOL" settle_checkpoint=0 checkpoint=0 name=spheres
  fi
  KEEP_FIELDS=0 SHAPE="$shape" ASPECT="$aspect" SEEDS="$3" FS="$4" PROTOCOL="$protocol" ALSO="" JOBS="${JOBS:-1}" \
    SETTLE_CHECKPOINT="$settle_checkpoint" CHECKPOINT="$checkpoint" STORE="$STORES/silo3d_rods_elongation_$name" \
    bash "$ROOT/examples/silo3d_rotating/rods_fig2c.sh" "$1" "$RUN_DIR/$name"
}

for n in $STAGES; do stage "$n" > /dev/null || exit 2; done
if [ "$ACTION" = keep ]; then
  for aspect in 4.0 2.5 3.3; do
    [ -d "$RUN_DIR/L$aspect" ] && campaign keep "$aspect" "$FIRST $SECOND" "0 0.32 1.28"
  done
  [ -d "$RUN_DIR/spheres" ] && campaign keep spheres "$FIRST $SECOND $THIRD" "0 0.32 1.28"
  exit 0
fi
for n in $STAGES; do
  IFS="|" read -r aspect seeds fs <<< "$(stage "$n")"
  echo "[$(date +%H:%M:%S)] rods_elongation: stage $n: L/d = $aspect, seeds $seeds, f = $fs Hz"
  campaign run "$aspect" "$seeds" "$fs"
done
