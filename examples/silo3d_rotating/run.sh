#!/bin/bash
# Flow rate of the rotating-bottom silo (inputs/silo3d_rotating/in.silo3d_rotating,
# the paper's silo with 10000 spheres) against the bottom's rotation
# frequency, for a few orifice sizes, then the analysis of these runs (not
# of others in RUN_DIR) into RUN_DIR/analysis: Q(f, D) tables, Beverloo
# and exponential fits, plots, coarse-grained fields.
#
#   bash examples/silo3d_rotating/run.sh [RUN_DIR]   (default: examples/silo3d_rotating/runs)
#   bash examples/silo3d_rotating/run.sh --help      prints this text
#
# Every run starts from one settled packing per seed (made once, then
# reused); the flow is kept stationary by reinjecting the grains at the top.
# Resumable: a run whose directory holds `finished` is not run again, and
# an interrupted discharge goes on from its last checkpoint (a restart file
# every CHECKPOINT s of discharge; analysis.campaign.checkpoint cuts its records back
# to it), so that an interruption loses at most CHECKPOINT s of each run.
# A run can be made longer: the same command with a larger DISCHARGE
# resumes it and runs it to the new end (its run.txt then ends with the
# new discharge_time). A finished run keeps its last checkpoint for this;
# one without (restored from an archive, or finished before run.sh kept
# it) is skipped.
#
# Environment (defaults in brackets):
#   DS       orifice diameters in m          ["0.042 0.06"]
#   FS       rotation frequencies in Hz      ["0 0.16 0.32 0.64 0.96 1.28"]
#            (DS="" or FS="": only the packings are made)
#   SEEDS    primes > 10000, one packing each ["32452843"]
#   DT_FRACTION  dt = t_c/DT_FRACTION        [40]
#   DISCHARGE    simulated seconds after the opening [2.0]
#   TRANSIENT    seconds after the opening left out of Q [0.5]
#   DISCHARGE_AT "f T" pairs: at the frequency f (one of FS, as written
#            there) the discharge lasts T s instead of DISCHARGE      [""]
#   TRANSIENT_AT "f T" pairs: at the frequency f, T s are left out of Q
#            instead of TRANSIENT (the analysis's --transient-at)     [""]
#            (a transient that lasts a part of a turn of the bottom is
#            shorter at faster f, and so can the runs be)
#   PACKINGS a directory of kept packings, packing_s<seed>.restart.xz or
#            packing_s<seed>.restart (doc/data/silo3d_rods/packings): a
#            seed found there is unpacked instead of settled, once its
#            packing_s<seed>_run.txt says the same SHAPE and ASPECT  [""]
#   FIELDS   "D f" pairs whose runs also dump grains and contacts for the
#            coarse-grained fields            ["0.06 0 0.06 0.32 0.06 1.28"]
#   JOBS     runs at once (serial LIGGGHTS processes) [1]
#   SHAPE    sphere | rod (spherocylinders, L = 20 mm) | clump (the rods'
#            stock peer: 10 glued spheres, fix multisphere)  [sphere]
#   ASPECT   rods and clumps: L/d (the paper's 2.5, 3.3, 4.0) [3.3]
#   REINJECT 1: discharged grains re-enter at the top; 0: they leave
#            (clumps: always 0, and no dumps: FIELDS is ignored)  [1]
#   DECK_VARS    more deck variables, "name value" pairs, e.g. "quick 1 N 900"
#            (the deck's parameters: inputs/silo3d_rotating/in.silo3d_rotating) [""]
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
#   ANALYSE  0: no analysis after the runs (a driver that runs a part
#            of a campaign analyses the whole itself)                [1]
#   SILOKIT_LIGGGHTS  the LIGGGHTS binary            [build/bin/liggghts]
#   SILOKIT_INPUTS    the inputs/ directory whose decks are run [inputs]
#            (a long campaign runs frozen copies of the binary and the
#            decks: LIGGGHTS reads a deck as it runs)
#   PYTHON   the Python that runs the analysis (with numpy) [/usr/bin/python3]
#
# Example: the quick silo (900 spheres, orifice 5 cm) at rest and at
# 0.32 Hz, 0.6 s of discharge each, into /tmp/silo3d_quick (a few minutes):
#   DS=0.05 FS="0 0.32" DISCHARGE=0.6 TRANSIENT=0.2 FIELDS="" DECK_VARS="quick 1" \
#       bash examples/silo3d_rotating/run.sh /tmp/silo3d_quick

# --help: the comment block above, without its "# "
case "${1:-}" in
  -h|--help) awk 'NR > 1 { if (!/^#/) exit; sub(/^# ?/, ""); print }' "$0"; exit 0 ;;
esac
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
RUN_DIR="${1:-$ROOT/examples/silo3d_rotating/runs}"
# absolute: each run works in its own folder, and reads the packing by path
RUN_DIR="$(realpath -m "$RUN_DIR")"
# (DS, FS and FIELDS set but empty mean none, not the defaults: FS="" only
# settles the packings)
DS="${DS-0.042 0.06}"
FS="${FS-0 0.16 0.32 0.64 0.96 1.28}"
SEEDS="${SEEDS:-32452843}"
DT_FRACTION="${DT_FRACTION:-40}"
DISCHARGE="${DISCHARGE:-2.0}"
TRANSIENT="${TRANSIENT:-0.5}"
DISCHARGE_AT="${DISCHARGE_AT:-}"
TRANSIENT_AT="${TRANSIENT_AT:-}"
PACKINGS="${PACKINGS:-}"
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
ANALYSE="${ANALYSE:-1}"
[ -z "$PEER_OF" ] || [ "$SHAPE" = clump ] || { echo "run.sh: PEER_OF places clumps on rods: it needs SHAPE=clump" >&2; exit 2; }
# (LIGGGHTS keeps the first -var of a name: the shape is added last, so
# that the rods' poses can be written with the same variables)
BASE=(-echo none -var inputs "$INPUTS" -var dt_fraction "$DT_FRACTION" -var aspect "$ASPECT")
set -- ${DECK_VARS:-}
[ $(( $# % 2 )) -eq 0 ] || { echo "run.sh: DECK_VARS needs name value pairs, got: ${DECK_VARS}" >&2; exit 2; }
while [ $# -ge 2 ]; do BASE+=(-var "$1" "$2"); shift 2; done
COMMON=("${BASE[@]}" -var shape "$SHAPE")

value_at() {   # value_at KEY DEFAULT "k v k v ...": the v of the pair whose k is KEY, else DEFAULT
  local key=$1 value=$2
  set -- $3
  while [ $# -ge 2 ]; do [ "$1" = "$key" ] && value=$2; shift 2; done
  echo "$value"
}
check_pairs() {  # NAME "f T ...": pairs, each f one of FS and given once, each T a number >= 0
  local name=$1 list=$2 f seen=" " found
  set -- $list
  [ $(( $# % 2 )) -eq 0 ] || { echo "run.sh: $name needs \"f T\" pairs, got: $list" >&2; exit 2; }
  while [ $# -ge 2 ]; do
    found=0
    for f in $FS; do [ "$f" = "$1" ] && found=1; done
    [ $found = 1 ] || { echo "run.sh: $name: $1 is not one of FS ($FS), written as there" >&2; exit 2; }
    case "$seen" in *" $1 "*) echo "run.sh: $name: $1 is given more than once" >&2; exit 2 ;; esac
    seen="$seen$1 "
    [[ "$2" =~ ^[0-9]+([.][0-9]*)?$ ]] || { echo "run.sh: $name: $1 needs a time >= 0 in s, not '$2'" >&2; exit 2; }
    shift 2
  done
}
check_pairs DISCHARGE_AT "$DISCHARGE_AT"
check_pairs TRANSIENT_AT "$TRANSIENT_AT"
# each frequency's window must be inside its run
for f in $FS; do
  length=$(value_at "$f" "$DISCHARGE" "$DISCHARGE_AT") transient=$(value_at "$f" "$TRANSIENT" "$TRANSIENT_AT")
  awk -v u="$length" -v t="$transient" 'BEGIN { exit !(u + 0 > t + 0) }' || {
    echo "run.sh: at f = $f the discharge ($length s) must be longer than the transient left out ($transient s)" >&2; exit 2; }
done
TRANSIENT_ARGS=()
set -- $TRANSIENT_AT
while [ $# -ge 2 ]; do TRANSIENT_ARGS+=(--transient-at "$1" "$2"); shift 2; done
[ -z "$PACKINGS" ] || [ -d "$PACKINGS" ] || { echo "run.sh: PACKINGS: no directory $PACKINGS" >&2; exit 2; }
[ -z "$PACKINGS" ] || [ -z "$PEER_OF" ] || { echo "run.sh: PEER_OF makes the clumps' packings from the rods': no PACKINGS with it" >&2; exit 2; }

mkdir -p "$RUN_DIR"
log() { echo "[$(date +%H:%M:%S)] silo3d_rotating: $*"; }

settle() {   # one packing per seed
  local seed=$1 dir="$RUN_DIR/packing_s$1"
  [ -f "$dir/finished" ] && return 0
  mkdir -p "$dir"
  local kept="$PACKINGS/packing_s$seed.restart"
  if [ -n "$PACKINGS" ] && [ -f "$kept.xz" -o -f "$kept" ]; then
    # a restart file does not say what it holds: its settling's run.txt does
    local info="$PACKINGS/packing_s${seed}_run.txt" shape aspect
    [ -f "$info" ] || { log "FAILED: $info, the kept packing's parameters, is missing"; return 1; }
    shape=$(awk '$1 == "shape" { print $2 }' "$info"); aspect=$(awk '$1 == "aspect" { print $2 }' "$info")
    if [ "$shape" != "$SHAPE" ] || { [ "$SHAPE" != sphere ] && ! awk -v a="$aspect" -v b="$ASPECT" 'BEGIN { exit !(a + 0 == b + 0) }'; }; then
      log "FAILED: the kept packing of seed $seed holds shape $shape, aspect $aspect ($info), not SHAPE=$SHAPE ASPECT=$ASPECT"
      return 1
    fi
    if [ -f "$kept.xz" ]; then xz -dc "$kept.xz" > "$dir/packing.restart.part"; else cp "$kept" "$dir/packing.restart.part"; fi
    mv "$dir/packing.restart.part" "$dir/packing.restart"
    cp "$info" "$dir/run.txt"
    log "packing of seed $seed: the kept one, $kept$([ -f "$kept.xz" ] && echo .xz)"
    touch "$dir/finished"
    return 0
  fi
  [ -z "$PACKINGS" ] || log "seed $seed: no kept packing in $PACKINGS, settled here"
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
    [ "$SETTLE_CHECKPOINT" = 0 ] || resume=$(analysis analysis.campaign.checkpoint settle-resume "$dir")
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
  analysis analysis.campaign.checkpoint clean "$dir"
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
  local D=$1 f=$2 seed=$3 dir="$RUN_DIR/D${1}_f${2}_s${3}" dump=0 start resume length
  length=$(value_at "$f" "$DISCHARGE" "$DISCHARGE_AT")
  if [ -f "$dir/finished" ]; then
    local ran
    ran=$(awk '$1 == "discharge_time" { t = $2 } END { print t }' "$dir/run.txt")
    if awk -v a="$ran" -v b="$length" 'BEGIN { exit !(a + 0 == b + 0) }'; then
      log "D $D f $f seed $seed: done before, skipped"; return 0
    elif awk -v a="$ran" -v b="$length" 'BEGIN { exit !(a + 0 < b + 0) }' \
        && [ -n "$(analysis analysis.campaign.checkpoint last "$dir")" ]; then
      # resume cuts run.txt's `finished` line and the records after the checkpoint
      log "D $D f $f seed $seed: done before with a discharge of $ran s: made longer, to $length s"
      rm "$dir/finished"
    else
      log "D $D f $f seed $seed: done before with a discharge of $ran s, not $length: skipped (kept as it is)"
      return 0
    fi
  fi
  mkdir -p "$dir"
  wants_fields "$D" "$f" && dump=0.05
  start=$(date +%s)
  # after an interruption: the last checkpoint's variables, records cut back to it
  resume=$(analysis analysis.campaign.checkpoint resume "$dir")
  if [ -n "$resume" ]; then
    log "D $D f $f seed $seed: resuming ($resume)"
  else
    log "D $D f $f seed $seed: running $length s (dumps every $dump s)"
    : > "$dir/screen.txt"
  fi
  # $resume: "-var name value" words, none with spaces
  (cd "$dir" && "${UNBUFFERED[@]}" "$LIGGGHTS" -in "$DECK" "${COMMON[@]}" -var seed "$seed" -var read_packing 1 \
      -var packing "$RUN_DIR/packing_s$seed/packing.restart" -var reinject "$REINJECT" -var D "$D" -var f "$f" \
      -var discharge_time "$length" -var dump_every_time "$dump" -var checkpoint_every_time "$CHECKPOINT" \
      $resume >> screen.txt 2>&1) \
      || { log "D $D f $f seed $seed: FAILED, see $dir/screen.txt"; return 1; }
  # LIGGGHTS ends a run it got SIGINT or SIGTERM for with exit status 0
  # (doc/liggghts_quirks.md): only the deck's `finished` line in run.txt says
  # that the discharge reached its end
  grep -q '^finished ' "$dir/run.txt" || {
    log "D $D f $f seed $seed: stopped before the end of its discharge (SIGINT/SIGTERM?); the same command resumes it"
    return 1; }
  touch "$dir/finished"
  analysis analysis.campaign.checkpoint clean "$dir" --keep-last
  log "D $D f $f seed $seed: $(grep -a 'done at' "$dir/screen.txt" | sed 's/silo3d_rotating: //') ($(( $(date +%s) - start )) s)"
}

for seed in $SEEDS; do settle "$seed"; done
RUNS=()
for seed in $SEEDS; do
  for D in $DS; do
    for f in $FS; do
      RUNS+=("$RUN_DIR/D${D}_f${f}_s${seed}")
      while [ "$(jobs -rp | wc -l)" -ge "$JOBS" ]; do wait -n || true; done
      discharge "$D" "$f" "$seed" &
    done
  done
done
wait
if [ -z "$DS" ] || [ -z "$FS" ]; then log "packings made (no D or f given: no runs)"; exit 0; fi
[ "$ANALYSE" != 0 ] || { log "all runs done (ANALYSE=0: not analysed)"; exit 0; }
# only this command's runs: other runs in RUN_DIR (other FS, DS or SEEDS)
# may have other windows than its TRANSIENT and TRANSIENT_AT
log "all runs done; analysing the ${#RUNS[@]} runs of DS, FS and SEEDS"
analysis analysis.silo3d_rotating "${RUNS[@]}" --out "$RUN_DIR/analysis" --transient "$TRANSIENT" \
    "${TRANSIENT_ARGS[@]}"
