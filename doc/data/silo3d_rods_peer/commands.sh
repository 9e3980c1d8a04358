#!/bin/bash
# How these records were made (2026-11-25, the deck of 77a20be; frozen binary
# and inputs): the glued-sphere peer on the quick silo (Dc = 0.1188 m,
# D = 0.05 m): 900 rods (ours) or 900 clumps of 10 spheres (stock fix
# multisphere), L/d = 3.3, settled 1.0 s, no reinjection (clumps cannot be
# reinjected), f = 0 and 0.32 Hz, two packings each, 1.0 s of discharge.
# Run from the repository root; resumes.
for shape in rod clump; do
  SHAPE=$shape ASPECT=3.3 REINJECT=0 DS="0.05" FS="0 0.32" SEEDS="32452843 49979687" DT_FRACTION=40 \
    DISCHARGE=1.0 TRANSIENT=0.1 FIELDS="" JOBS=1 DECK_VARS="quick 1 N 900 settle_time 1.0" \
    bash examples/silo3d_rotating/run.sh runs/peer_$shape
done
# flow_rate_*.md and flow_rate_runs_*.md are runs/peer_<shape>/analysis/flow_rate*.md
# (run.sh's analysis, --transient 0.1); loop_times.txt sums each run's 'Loop time' lines.
# The time step of the clumps (2026-11-25, commit 8bd3392's deck): the two
# quick clump packings above, f = 0.32 Hz, run at the rods' dt
# (3.08993237597775e-06 s) instead of the deck's half; records
# clump_dt_rods_*, table flow_rate_runs_clump_dt_rods.md (--transient 0.1).
ROOT="$(pwd)"
for s in 32452843 49979687; do
  mkdir -p runs/peer_dt/D0.05_f0.32_s$s && (cd runs/peer_dt/D0.05_f0.32_s$s && "$ROOT/build/bin/liggghts" \
    -in "$ROOT/inputs/silo3d_rotating/in.silo3d_rotating" -var inputs "$ROOT/inputs" -var quick 1 -var N 900 \
    -var shape clump -var aspect 3.3 -var dt_fraction 40 -var dt 3.08993237597775e-06 -var read_packing 1 \
    -var packing "$ROOT/runs/peer_clump/packing_s$s/packing.restart" -var reinject 0 -var D 0.05 -var f 0.32 \
    -var seed $s -var discharge_time 1.0)
done

# The full-size pair (2026-11-25, binary of commit 5bb37c6, the C++ of main
# since; inputs and run.sh of 5bb37c6, then of fb386f2 when resumed): the
# rods' first packing (../silo3d_rods/packings/), clumps placed on it and
# relaxed 0.1 s, then f = 0 and 0.32 Hz at the rods' dt; and the rods of
# the same packing without reinjection, the pair's other half.
# full_D0.06_s32452843/: <shape>_f<f>/ run.txt, discharge.txt and
# loop_times.txt (every 'Loop time' line of the run's screen.txt: chunks run
# again after a stop included); clump_packing_loop_times.txt (the
# relaxation); flow_rate_{runs,windows}_<shape>.md from
#   /usr/bin/python3 -m analysis.silo3d_rotating full_D0.06_s32452843/<shape>_f* --out OUT \
#       --no-fields --transient 0.5 --window-width 0.5
# The clump f = 0 run was stopped at 0.29 s, resumed from its 0.25 s
# checkpoint, stopped at 0.90 s by the end of a session and resumed from
# its 0.75 s checkpoint; the clump f = 0.32 Hz run was stopped at 1.25 s by
# the end of a session and resumed from its 1.25 s checkpoint; the rods ran
# uninterrupted.
# With runs/rods/packing_s32452843 and runs/rods_out/packing_s32452843 made
# from the kept packing (the rods without reinjection in a directory of
# their own: run.sh names runs by D, f and seed only):
SHAPE=clump PEER_OF=runs/rods RELAX=0.1 ASPECT=3.3 DS="0.06" FS="0 0.32" SEEDS="32452843" DT_FRACTION=40 \
  DISCHARGE=1.5 TRANSIENT=0.5 JOBS=1 DECK_VARS="dt 3.08993237597775e-06" bash examples/silo3d_rotating/run.sh runs/peer_full
SHAPE=rod ASPECT=3.3 DS="0.06" FS="0 0.32" SEEDS="32452843" DT_FRACTION=40 REINJECT=0 \
  DISCHARGE=1.5 TRANSIENT=0.5 JOBS=1 bash examples/silo3d_rotating/run.sh runs/rods_out
