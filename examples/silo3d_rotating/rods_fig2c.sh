#!/bin/bash
# The rods' campaign for the paper's Fig. 2c (doc/silo3d_rotating.md, "The
# campaign"): D = 60 mm, L/d = 3.3, six frequencies in three packings, each
# frequency with its own discharge and transient, two runs at a time, carried
# from session to session (a session's machine may not outlive it) through
# the repository (analysis.campaign.silo3d_carry): the finished runs' reduced records
# in a store in doc/data, the unfinished runs' last checkpoints and the
# settled packings in carry/<store's name>/. With ASPECT, PROTOCOL and STORE
# it runs another aspect ratio's campaign (rods_elongation.sh).
#
#   bash examples/silo3d_rotating/rods_fig2c.sh run  RUN_DIR
#       puts the store's runs into RUN_DIR (finished ones as done, unfinished
#       ones at their last checkpoint; a finished one shorter than PROTOCOL
#       says, at its last checkpoint carried in the history, if any: it is
#       made longer), runs what is left with run.sh and,
#       when all are done, analyses the whole campaign into RUN_DIR/analysis
#   bash examples/silo3d_rotating/rods_fig2c.sh keep RUN_DIR
#       before the machine goes (the runs may go on): analyses the finished
#       runs not analysed or archived before (their orifice tables and
#       fields), archives them into the store
#       and carries the unfinished ones' last checkpoints and the packings;
#       then commit the store and carry/
#
# Environment (defaults in brackets):
#   FS, SEEDS  run only these of the protocol's frequencies, of the seeds
#              [all: "0 0.16 0.32 0.64 0.96 1.28", "32452843 15485863 49979687"]
#   DS         the orifice diameter, m  [0.06]
#   ASPECT     the rods' L/d            [3.3]
#   SHAPE      rod | sphere: the grains (the elongation campaign's spheres
#              at L/d = 1 run this way too; ASPECT is then not used)  [rod]
#   PACKINGS   the settled packings     [carry/<store's name>/packings when
#              it exists, else none: each seed is settled (0.6 CPU-h at 3.3)]
#   SETTLE_CHECKPOINT  s of settling between checkpoints, so that a
#              settling can be carried too; 0: in one run, which gives the
#              3.3 campaign's packings again to the printed digits (with
#              checkpoints the trajectory differs at round-off)   [0]
#   PROTOCOL   "f discharge transient" triples, s: each frequency's run
#              length and the start left out of Q   [the campaign's, below]
#   STORE      the campaign's store        [doc/data/silo3d_rods_fig2c]
#   ALSO       finished runs of the same protocol archived elsewhere in the
#              repository, taken as done   [the four below]
#   KEEP_FIELDS 1: a finished run's archive keeps its maps (fields.npz);
#              0: its flow rate and orifice table only (about 0.1 MB a run
#              instead of 0.4: a campaign whose pages use no maps)   [1]
#   JOBS [2]; SILOKIT_LIGGGHTS, DECK_VARS, CHECKPOINT, PYTHON go to run.sh
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
ACTION="${1:-}"
RUN_DIR="${2:-}"
[ -n "$RUN_DIR" ] && { [ "$ACTION" = run ] || [ "$ACTION" = keep ]; } || {
  echo "usage: bash examples/silo3d_rotating/rods_fig2c.sh run|keep RUN_DIR" >&2; exit 2; }
# f = 0 and 0.16 Hz: 8 s, Q over 4-8 s (the transient lasts most of a turn
# at 0.16 Hz); 0.32 Hz: 4 s, Q over 2-4 s; faster: 4 s, Q over 1-4 s (from
# 0.64 turns on: the transient is over by then, tested at 0.64 Hz)
PROTOCOL="${PROTOCOL:-0 8 4  0.16 8 4  0.32 4 2  0.64 4 1  0.96 4 1  1.28 4 1}"
STORE="${STORE:-$ROOT/doc/data/silo3d_rods_fig2c}"
ALSO="${ALSO-$ROOT/doc/data/silo3d_rods_drop_8s/D0.06_f0_s32452843 $ROOT/doc/data/silo3d_rods_drop_8s/D0.06_f0.16_s32452843 $ROOT/doc/data/silo3d_rods_drop_8s/D0.06_f0.16_s15485863 $ROOT/doc/data/silo3d_rods_transient/D0.06_f0.64_s32452843}"
SEEDS="${SEEDS:-32452843 15485863 49979687}"
DS="${DS:-0.06}"
PYTHON="${PYTHON:-/usr/bin/python3}"
analysis() { PYTHONPATH="$ROOT${PYTHONPATH:+:$PYTHONPATH}" "$PYTHON" -m "$@"; }
ASPECT="${ASPECT:-3.3}"
SHAPE="${SHAPE:-rod}"
case "$SHAPE" in rod|sphere) ;; *) echo "rods_fig2c.sh: SHAPE is rod or sphere, got: $SHAPE" >&2; exit 2 ;; esac
CARRIED_PACKINGS="$(analysis analysis.campaign.silo3d_carry carry-dir "$STORE")/packings"
PACKINGS="${PACKINGS:-}"
if [ -z "$PACKINGS" ] && [ -d "$CARRIED_PACKINGS" ]; then PACKINGS="$CARRIED_PACKINGS"; fi
SETTLE_CHECKPOINT="${SETTLE_CHECKPOINT:-0}"
case "${KEEP_FIELDS:-1}" in 0|1) ;; *) echo "rods_fig2c.sh: KEEP_FIELDS is 0 or 1, got: $KEEP_FIELDS" >&2; exit 2 ;; esac
# the dumps keep the orifice region and the column over the axis (the
# axial acceleration, analysis.silo3d_rotating.acceleration)
COLUMN=(--dump-cylinder 0.025 0.2)

set -- $PROTOCOL
[ $# -gt 0 ] && [ $(( $# % 3 )) -eq 0 ] || { echo "rods_fig2c.sh: PROTOCOL needs \"f discharge transient\" triples, got: $PROTOCOL" >&2; exit 2; }
ALL_FS="" DISCHARGE_AT="" TRANSIENT_AT="" ANALYSIS_AT=()
while [ $# -ge 3 ]; do
  ALL_FS="$ALL_FS $1"
  ANALYSIS_AT+=(--transient-at "$1" "$3")
  shift 3
done
FS="${FS:-$ALL_FS}"
for f in $FS; do
  set -- $PROTOCOL
  found=0
  while [ $# -ge 3 ]; do
    if [ "$1" = "$f" ]; then DISCHARGE_AT="$DISCHARGE_AT $1 $2" TRANSIENT_AT="$TRANSIENT_AT $1 $3" found=1; fi
    shift 3
  done
  [ $found = 1 ] || { echo "rods_fig2c.sh: FS: $f is not one of the protocol's frequencies ($ALL_FS)" >&2; exit 2; }
done

if [ "$ACTION" = keep ]; then
  [ -d "$RUN_DIR" ] || { echo "rods_fig2c.sh: no run directory $RUN_DIR" >&2; exit 2; }
  # the finished runs' orifice tables and fields come from their dumps,
  # which the store does not keep: analyse them before they are archived
  # (runs archived, or analysed since they finished, are not read again)
  pending="$(analysis analysis.campaign.silo3d_carry to-analyse "$RUN_DIR" "$STORE")"
  if [ -n "$pending" ]; then
    mapfile -t pending <<< "$pending"
    analysis analysis.silo3d_rotating "${pending[@]}" --out "$RUN_DIR/analysis" "${ANALYSIS_AT[@]}"
  fi
  analysis analysis.campaign.silo3d_carry keep "$RUN_DIR" "$STORE" "${COLUMN[@]}" \
    $([ "${KEEP_FIELDS:-1}" = 0 ] && echo --no-fields)
  exit 0
fi

analysis analysis.campaign.silo3d_carry restore "$STORE" "$RUN_DIR" $([ -n "$ALSO" ] && echo --also $ALSO)
# an archived run shorter than the protocol (one made longer since) goes on
# from its last checkpoint carried in the history, or, never carried, runs
# again from its packing
LENGTHS=()
set -- $DISCHARGE_AT
while [ $# -ge 2 ]; do LENGTHS+=(--length "$1" "$2"); shift 2; done
analysis analysis.campaign.silo3d_carry reopen "$STORE" "$RUN_DIR" "${LENGTHS[@]}"
# (DISCHARGE and TRANSIENT are each frequency's, from DISCHARGE_AT and
# TRANSIENT_AT: run.sh needs defaults, never used)
SHAPE="$SHAPE" ASPECT="$ASPECT" DS="$DS" FS="$FS" SEEDS="$SEEDS" PACKINGS="$PACKINGS" SETTLE_CHECKPOINT="$SETTLE_CHECKPOINT" \
  DISCHARGE=1 TRANSIENT=0 DISCHARGE_AT="$DISCHARGE_AT" TRANSIENT_AT="$TRANSIENT_AT" \
  FIELDS="$(for f in $FS; do echo -n "$DS $f "; done)" JOBS="${JOBS:-2}" ANALYSE=0 \
  bash "$ROOT/examples/silo3d_rotating/run.sh" "$RUN_DIR"
# (Q, the orifice averages and the axial acceleration are whole for every
# run; the maps of a run restored from an archive hold only the kept
# cylinders: its maps are the fields.npz kept beside its records, if any)
if ! ls "$RUN_DIR"/D*_f*_s* -d 2>/dev/null | while read -r run; do [ -f "$run/finished" ] || exit 1; done; then
  echo "rods_fig2c.sh: runs left unfinished in $RUN_DIR: not analysed ('keep' carries them to the next session)"
elif [ -z "$(analysis analysis.campaign.silo3d_carry to-analyse "$RUN_DIR" "$STORE")" ]; then
  # a stage met again on resuming: its runs' dumps were read before
  echo "rods_fig2c.sh: every run in $RUN_DIR is archived in $STORE or analysed since it finished: not analysed again"
else
  # (the dumps of runs analysed before with the same settings are not read
  # again: runs/<label>/fields_source.txt)
  analysis analysis.silo3d_rotating "$RUN_DIR"/D*_f*_s* --out "$RUN_DIR/analysis" "${ANALYSIS_AT[@]}"
fi
