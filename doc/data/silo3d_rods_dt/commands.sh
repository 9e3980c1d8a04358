#!/bin/bash
# How these records were made (2026-11-24, the decks of b7718ff; the quick rods are the same at dc96eab): the quick
# rod silo (300 rods, L/d = 3.3, Dc = 0.1188 m, D = 0.05 m, 0.7 s of settling),
# f = 0.32 Hz, reinjection, 1.5 s of discharge, at dt = t_c/F for four F and
# four seeds. Run from the repository root; resumes.
ROOT=$(pwd)
for seed in 32452843 49979687 15485863 67867967; do
for F in 40 20 158 80; do
  d=runs/rods_dt/F${F}_s${seed}; [ -f $d/finished ] && continue; mkdir -p $d
  (cd $d && stdbuf -oL "$ROOT/build/bin/liggghts" -in "$ROOT/inputs/silo3d_rotating/in.silo3d_rotating" -echo none \
     -var inputs "$ROOT/inputs" -var quick 1 -var shape rod -var aspect 3.3 -var f 0.32 -var reinject 1 \
     -var discharge_time 1.5 -var dt_fraction $F -var seed $seed > screen.txt 2>&1) && touch $d/finished
done; done
# the table of doc/accuracy_cost_silo3d_rotating.md, one dt at a time:
for F in 20 40 80 158; do
  /usr/bin/python3 -m analysis.silo3d_rotating runs/rods_dt/F${F}_s* --out runs/rods_dt/analysis_F$F --transient 0.5 --no-fields
done
