#!/bin/bash
# How these records were made (2026-11-24/25, the deck of dc96eab; frozen
# binary and inputs): L/d = 3.3 rods, D = 60 mm, one packing (seed
# 32452843, settled 2 s), reinjection, 1.5 s of discharge, dumps every
# 0.05 s, one run per f. Run from the repository root; resumes.
SHAPE=rod ASPECT=3.3 DS="0.06" FS="0 0.16 0.32 0.64 1.28 0.96" SEEDS="32452843" DT_FRACTION=40 DISCHARGE=1.5 \
  TRANSIENT=0.5 FIELDS="0.06 0 0.06 0.16 0.06 0.32 0.06 0.64 0.06 1.28 0.06 0.96" JOBS=1 \
  bash examples/silo3d_rotating/run.sh runs/rods
# the tables here (orifice.md, flow_rate_runs.md, flow_rate_change.md,
# D*/orifice_timeseries.md) are those of the full dumps:
/usr/bin/python3 -m analysis.silo3d_rotating runs/rods/D0.06_f*_s* --out runs/rods/analysis --transient 0.5
# dump.cg.xz keeps the grains within r < 0.06 m and z < 0.05 m of each
# frame (the orifice cylinder r < 0.03 m, z < 0.01 m, plus the kernel's
# cut-off of 0.02 m and a margin), so that the orifice averages (but not
# p_c, which needs dump.contacts, nor the maps) come back from it:
reduce() {
  /usr/bin/python3 - "$1" "$2" <<'PY'
import sys
lines = open(sys.argv[1]).read().splitlines()
out, i = open(sys.argv[2], "w"), 0
while i < len(lines):
    head, n = lines[i:i + 9], int(lines[i + 3])
    columns = head[8].split()[2:]
    ix, iy, iz = (columns.index(c) for c in ("x", "y", "z"))
    keep = [row for row in lines[i + 9:i + 9 + n]
            if float(row.split()[iz]) < 0.05 and float(row.split()[ix]) ** 2 + float(row.split()[iy]) ** 2 < 0.06 ** 2]
    head[3] = str(len(keep))
    out.write("\n".join(head + keep) + "\n")
    i += 9 + n
PY
}
for run in runs/rods/D0.06_f*_s32452843; do
  reduce "$run/dump.cg" /tmp/dump.cg.reduced && xz -9 -c /tmp/dump.cg.reduced > "doc/data/silo3d_rods/$(basename "$run")/dump.cg.xz"
done
# check: decompress into copies of the run directories (run.txt,
# discharge.txt, reinject.txt, dump.cg) and compare the orifice table:
#   /usr/bin/python3 -m analysis.silo3d_rotating COPIES/D* --out check --transient 0.5

# A second packing (seed 15485863), f = 0 and 0.16 Hz, the same protocol
# (2026-11-25, same frozen binary and inputs):
SHAPE=rod ASPECT=3.3 DS="0.06" FS="0 0.16" SEEDS="15485863" DT_FRACTION=40 DISCHARGE=1.5 TRANSIENT=0.5 \
  FIELDS="0.06 0 0.06 0.16" JOBS=2 bash examples/silo3d_rotating/run.sh runs/rods_s2
# two_packings/: both packings' f = 0 and 0.16 Hz runs together
/usr/bin/python3 -m analysis.silo3d_rotating runs/rods/D0.06_f0_s32452843 runs/rods/D0.06_f0.16_s32452843 \
    runs/rods_s2/D0.06_f0_s15485863 runs/rods_s2/D0.06_f0.16_s15485863 --out runs/two_packings --transient 0.5
for run in runs/rods_s2/D0.06_f*_s15485863; do
  reduce "$run/dump.cg" /tmp/dump.cg.reduced && xz -9 -c /tmp/dump.cg.reduced > "doc/data/silo3d_rods/$(basename "$run")/dump.cg.xz"
done

# A third packing (seed 49979687), f = 0 and 0.16 Hz, the same protocol
# (2026-11-25, same frozen binary; the inputs of commit e50d57b):
SHAPE=rod ASPECT=3.3 DS="0.06" FS="0 0.16" SEEDS="49979687" DT_FRACTION=40 DISCHARGE=1.5 TRANSIENT=0.5 \
  FIELDS="0.06 0 0.06 0.16" JOBS=1 bash examples/silo3d_rotating/run.sh runs/rods_s3
# three_packings/: the three packings' f = 0 and 0.16 Hz runs together
/usr/bin/python3 -m analysis.silo3d_rotating runs/rods/D0.06_f0_s32452843 runs/rods/D0.06_f0.16_s32452843 \
    runs/rods_s2/D0.06_f0_s15485863 runs/rods_s2/D0.06_f0.16_s15485863 \
    runs/rods_s3/D0.06_f0_s49979687 runs/rods_s3/D0.06_f0.16_s49979687 --out runs/three_packings --transient 0.5
for run in runs/rods_s3/D0.06_f*_s49979687; do
  reduce "$run/dump.cg" /tmp/dump.cg.reduced && xz -9 -c /tmp/dump.cg.reduced > "doc/data/silo3d_rods/$(basename "$run")/dump.cg.xz"
done

# 2026-11-25, a new machine (binary and inputs of commit 5bb37c6, frozen):
# the packings of seeds 32452843 and 15485863 settled again (packings/:
# their restart files, and how to use them), then the second orifice,
# D = 54 mm, f = 0, from the second packing (its 0.16 Hz run was stopped):
SHAPE=rod ASPECT=3.3 DS="0.054" FS="0 0.16" SEEDS="15485863" DT_FRACTION=40 DISCHARGE=1.5 TRANSIENT=0.5 \
  FIELDS="0.054 0 0.054 0.16" JOBS=1 bash examples/silo3d_rotating/run.sh runs/rods_s2
reduce runs/rods_s2/D0.054_f0_s15485863/dump.cg /tmp/dump.cg.reduced && \
  xz -9 -c /tmp/dump.cg.reduced > doc/data/silo3d_rods/D0.054_f0_s15485863/dump.cg.xz
# the table of doc/silo3d_rotating.md ("Orifices of 45–80 mm"): the f = 0 runs
# of both orifices, from copies with dump.cg decompressed from dump.cg.xz:
#   /usr/bin/python3 -m analysis.silo3d_rotating COPIES/D0.054_f0_s15485863 COPIES/D0.06_f0_s* --out an --transient 0.5
# The long runs (4 s, both orifices, same packing; resumable):
SHAPE=rod ASPECT=3.3 DS="0.054 0.06" FS="0" SEEDS="15485863" DT_FRACTION=40 DISCHARGE=4.0 TRANSIENT=1.0 \
  FIELDS="0.054 0 0.06 0" JOBS=2 CHECKPOINT=0.25 bash examples/silo3d_rotating/run.sh runs/long

# Orifices of 45, 50 and 80 mm (2026-11-25, frozen binary of 5bb37c6),
# records in ../silo3d_rods_orifices/ (its README has the command). The
# 45 mm run clogged at 0.31 s and was stopped by hand at 0.535 s.
