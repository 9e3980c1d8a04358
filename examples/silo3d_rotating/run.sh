#!/bin/bash
# Flow rate of the rotating-bottom silo (inputs/silo3d_rotating/in.silo3d_rotating,
# the paper's silo with 10000 spheres) against the bottom's rotation
# frequency, for a few orifice sizes, then the analysis: Q(f, D) tables,
# Beverloo and exponential fits, plots, coarse-grained fields.
#
#   bash examples/silo3d_rotating/run.sh [RUN_DIR]
#
# Every run starts from one settled packing per seed (made once, then
# reused); the flow is kept stationary by reinjecting the grains at the top.
# Resumable: a run whose directory holds `finished` is not run again, and
# an interrupted discharge goes on from its last checkpoint (a restart file
# every CHECKPOINT s of discharge; analysis.checkpoint cuts its records back
# to it), so that a session's end loses at most CHECKPOINT s of each run.
# An unfinished run can be made longer: the same command with a larger
# DISCHARGE resumes it and runs it to the new end (its run.txt then ends
# with the new discharge_time); a finished one has no checkpoint left.
# Environment (defaults in brackets):
#   DS       orifice diameters in m          ["0.042 0.06"]
#   FS       rotation frequencies in Hz      ["0 0.16 0.32 0.64 0.96 1.28"]
#            (DS="" or FS="": only the packings are made)
#   SEEDS    primes > 10000, one packing each ["32452843"]
#   DT_FRACTION  dt = t_c/DT_FRACTION        [40]
#   DISCHARGE    simulated seconds after the opening [2.0]
#   TRANSIENT    seconds after the opening left out of Q [0.5]
#   FIELDS   "D f" pairs whose runs also dump grains and contacts for the
#            coarse-grained fields            ["0.06 0 0.06 0.32 0.06 1.28"]
#   JOBS     runs at once (serial LIGGGHTS processes) [1]
#   SHAPE    sphere | rod (spherocylinders, L = 20 mm) | clump (the rods'
#            stock peer: 10 glued spheres, fix multisphere)  [sphere]
#   ASPECT   rods and clumps: L/d (the paper's 2.5, 3.3, 4.0) [3.3]
#   REINJECT 1: discharged grains re-enter at the top; 0: they leave
#            (clumps: always 0, and no dumps: FIELDS is ignored)  [1]
#   DECK_VARS    more deck variables, "name value" pairs, e.g. "quick 1 N 900" [""]
#   CHECKPOINT   s of discharge between checkpoints, 0: none      [0.25]
#   SETTLE_CHECKPOINT  s of settling between checkpoints, 0: none   [0]
#            (a settling cut short then goes on from its last one; a
#            settling with checkpoints is another trajectory, at round-off,
#            than one without, so the default keeps a seed's packing that
#            of the kept packings, doc/data/silo3d_rods/packings)
#   PEER_OF  clumps: a rod campaign's RUN_DIR (same ASPECT and SEEDS); each
#            clump packing is then that seed's rod packing with a clump on
#            every rod (write_poses, read_poses: fix insert/poses), relaxed
#            RELAX s in the closed silo, instead of a settled gas   [""]
#   RELAX    s the clumps relax at the rods' poses                 [0.1]
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
RUN_DIR="${1:-$ROOT/examples/silo3d_rotating/runs}"
# (DS, FS and FIELDS set but empty mean none, not the defaults: FS="" only
# settles the packings)
DS="${DS-0.042 0.06}"
FS="${FS-0 0.16 0.32 0.64 0.96 1.28}"
SEEDS="${SEEDS:-32452843}"
DT_FRACTION="${DT_FRACTION:-40}"
DISCHARGE="${DISCHARGE:-2.0}"
TRANSIENT="${TRANSIENT:-0.5}"
FIELDS="${FIELDS-0.06 0 0.06 0.32 0.06 1.28}"
JOBS="${JOBS:-1}"
SHAPE="${SHAPE:-sphere}"
ASPECT="${ASPECT:-3.3}"
REINJECT="${REINJECT:-1}"
CHECKPOINT="${CHECKPOINT:-0.25}"
SETTLE_CHECKPOINT="${SETTLE_CHECKPOINT:-0}"
if [ "$SHAPE" = clump ]; then REINJECT=0; FIELDS=""; fi
LIGGGHTS="${SILOKIT_LIGGGHTS:-$ROOT/build/bin/liggghts}"
# line-buffered output: progress reaches screen.txt as it happens, and a
# message of LIGGGHTS' Error::one (printed without a flush before
# MPI_Abort, doc/liggghts_quirks.md) is not lost
UNBUFFERED=(stdbuf -oL)
PYTHON="${PYTHON:-/usr/bin/python3}"
analysis() { PYTHONPATH="$ROOT${PYTHONPATH:+:$PYTHONPATH}" "$PYTHON" -m "$@"; }
# a long campaign runs frozen copies of the binary and the decks
# (SILOKIT_LIGGGHTS, SILOKIT_INPUTS): LIGGGHTS reads a deck as it runs
INPUTS="${SILOKIT_INPUTS:-$ROOT/inputs}"
DECK="$INPUTS/silo3d_rotating/in.silo3d_rotating"
PEER_OF="${PEER_OF:-}"
RELAX="${RELAX:-0.1}"
[ -z "$PEER_OF" ] || [ "$SHAPE" = clump ] || { echo "run.sh: PEER_OF places clumps on rods: it needs SHAPE=clump" >&2; exit 2; }
# (LIGGGHTS keeps the first -var of a name: the shape is added last, so
# that the rods' poses can be written with the same variables)
BASE=(-echo none -var inputs "$INPUTS" -var dt_fraction "$DT_FRACTION" -var aspect "$ASPECT")
set -- ${DECK_VARS:-}
[ $(( $# % 2 )) -eq 0 ] || { echo "run.sh: DECK_VARS needs name value pairs, got: ${DECK_VARS}" >&2; exit 2; }
while [ $# -ge 2 ]; do BASE+=(-var "$1" "$2"); shift 2; done
COMMON=("${BASE[@]}" -var shape "$SHAPE")

mkdir -p "$RUN_DIR"
log() { echo "[$(date +%H:%M:%S)] silo3d_rotating: $*"; }

settle() {   # one packing per seed
  local seed=$1 dir="$RUN_DIR/packing_s$1"
  [ -f "$dir/finished" ] && return 0
  mkdir -p "$dir"
  if [ -n "$PEER_OF" ]; then
    local rods="$PEER_OF/packing_s$seed/packing.restart"
    [ -f "$rods" ] || { log "FAILED: no rod packing $rods (PEER_OF)"; return 1; }
    log "clumps on the rods of $rods, relaxed $RELAX s, in $dir"
    (cd "$dir" && "${UNBUFFERED[@]}" "$LIGGGHTS" -in "$DECK" "${BASE[@]}" -var shape rod -var seed "$seed" \
        -var read_packing 1 -var packing "$rods" -var write_poses 1 -var poses rod_poses.dump \
        -var discharge_time 0 > screen_poses.txt 2>&1) || { log "FAILED: see $dir/screen_poses.txt"; return 1; }
    (cd "$dir" && "${UNBUFFERED[@]}" "$LIGGGHTS" -in "$DECK" "${COMMON[@]}" -var seed "$seed" -var read_poses 1 \
        -var poses rod_poses.dump -var settle_time "$RELAX" -var write_packing 1 -var discharge_time 0 \
        > screen.txt 2>&1) || { log "FAILED: see $dir/screen.txt"; return 1; }
  else
    local resume=""
    [ "$SETTLE_CHECKPOINT" = 0 ] || resume=$(analysis analysis.checkpoint settle-resume "$dir")
    if [ -n "$resume" ]; then
      log "settling the packing of seed $seed in $dir: resuming ($resume)"
    else
      log "settling the packing of seed $seed in $dir"
      : > "$dir/screen.txt"
    fi
    # $resume: "-var name value" words, none with spaces
    (cd "$dir" && "${UNBUFFERED[@]}" "$LIGGGHTS" -in "$DECK" "${COMMON[@]}" -var seed "$seed" -var write_packing 1 \
        -var discharge_time 0 -var settle_checkpoint_every_time "$SETTLE_CHECKPOINT" $resume >> screen.txt 2>&1) \
        || { log "FAILED: see $dir/screen.txt"; return 1; }
  fi
  # (a settling stopped by SIGINT/SIGTERM ends with status 0 but no packing)
  [ -f "$dir/packing.restart" ] || { log "seed $seed: stopped before its packing was written; the same command settles it again (from its last checkpoint, with SETTLE_CHECKPOINT)"; return 1; }
  touch "$dir/finished"
  analysis analysis.checkpoint clean "$dir"
}

wants_fields() {
  local D=$1 f=$2 pair
  set -- $FIELDS
  while [ $# -ge 2 ]; do
    [ "$1" = "$D" ] && [ "$2" = "$f" ] && return 0
    shift 2
  done
  return 1
}

discharge() {  # one (D, f, seed) run
  local D=$1 f=$2 seed=$3 dir="$RUN_DIR/D${1}_f${2}_s${3}" dump=0 start resume
  [ -f "$dir/finished" ] && { log "D $D f $f seed $seed: done before, skipped"; return 0; }
  mkdir -p "$dir"
  wants_fields "$D" "$f" && dump=0.05
  start=$(date +%s)
  # after an interruption: the last checkpoint's variables, records cut back to it
  resume=$(analysis analysis.checkpoint resume "$dir")
  if [ -n "$resume" ]; then
    log "D $D f $f seed $seed: resuming ($resume)"
  else
    log "D $D f $f seed $seed: running (dumps every $dump s)"
    : > "$dir/screen.txt"
  fi
  # $resume: "-var name value" words, none with spaces
  (cd "$dir" && "${UNBUFFERED[@]}" "$LIGGGHTS" -in "$DECK" "${COMMON[@]}" -var seed "$seed" -var read_packing 1 \
      -var packing "$RUN_DIR/packing_s$seed/packing.restart" -var reinject "$REINJECT" -var D "$D" -var f "$f" \
      -var discharge_time "$DISCHARGE" -var dump_every_time "$dump" -var checkpoint_every_time "$CHECKPOINT" \
      $resume >> screen.txt 2>&1) \
      || { log "D $D f $f seed $seed: FAILED, see $dir/screen.txt"; return 1; }
  # LIGGGHTS ends a run it got SIGINT or SIGTERM for with exit status 0
  # (doc/liggghts_quirks.md): only the deck's `finished` line in run.txt says
  # that the discharge reached its end
  grep -q '^finished ' "$dir/run.txt" || {
    log "D $D f $f seed $seed: stopped before the end of its discharge (SIGINT/SIGTERM?); the same command resumes it"
    return 1; }
  touch "$dir/finished"
  analysis analysis.checkpoint clean "$dir"
  log "D $D f $f seed $seed: $(grep -a 'done at' "$dir/screen.txt" | sed 's/silo3d_rotating: //') ($(( $(date +%s) - start )) s)"
}

for seed in $SEEDS; do settle "$seed"; done
for seed in $SEEDS; do
  for D in $DS; do
    for f in $FS; do
      while [ "$(jobs -rp | wc -l)" -ge "$JOBS" ]; do wait -n || true; done
      discharge "$D" "$f" "$seed" &
    done
  done
done
wait
if [ -z "$DS" ] || [ -z "$FS" ]; then log "packings made (no D or f given: no runs)"; exit 0; fi
log "all runs done; analysing"
analysis analysis.silo3d_rotating "$RUN_DIR"/D*_f*_s* --out "$RUN_DIR/analysis" --transient "$TRANSIENT"
