#!/usr/bin/env bash
# Does a tutorial's speed ratio depend on where the heap's chunks fall?
# Runs one LIGGGHTS tutorial that needs no other deck first (cut as
# bench/stock_tutorials.py cuts it) with two binaries alternately on one
# core, each run with the heap shifted by K bytes at start-up: a
# preloaded constructor mallocs K bytes and keeps them, so every later
# chunk sits K bytes further on. Same code, same allocations, other
# addresses. Prints one line per run and a table of
# t_b / t_a per offset (doc/build.md, "hydrogel_multicontact: what is left").
#
#   bash bench/heap_offset.sh [--quick] [A_BINARY] [B_BINARY]
#
# A_BINARY defaults to build/bin/liggghts, B_BINARY to Debian's
# /usr/bin/liggghts. --quick: 20 steps, one repetition, two offsets,
# output under bench/work/quick/. About 24 min for the defaults.
# Environment (defaults in brackets): DECK [hydrogel_multicontact/in.hydrogel_multicontact],
# STEPS [2000], REPS [3], OFFSETS ["0 16 48 112 240 496 1008 2032"], CPU [1],
# OUT [bench/results/heap_offset.txt]
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
case "${1:-}" in
  -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
  --quick) shift; STEPS=20 REPS=1 OFFSETS="0 16" OUT="$ROOT/bench/work/quick/heap_offset.txt" ;;
esac
A="${1:-$ROOT/build/bin/liggghts}"
B="${2:-/usr/bin/liggghts}"
DECK="${DECK:-hydrogel_multicontact/in.hydrogel_multicontact}"
STEPS="${STEPS:-2000}" REPS="${REPS:-3}" CPU="${CPU:-1}"
OFFSETS="${OFFSETS:-0 16 48 112 240 496 1008 2032}"
OUT="${OUT:-$ROOT/bench/results/heap_offset.txt}"
WORK="$ROOT/bench/work/heap_offset"
mkdir -p "$WORK" "$(dirname "$OUT")"

cat > "$WORK/shift.c" <<'C'
#include <stdlib.h>
__attribute__((constructor)) static void shift(void) {
  const char *s = getenv("SHIFT_BYTES");
  if (s && atoi(s) > 0) { void *volatile p = malloc((size_t)atoi(s)); (void)p; }
}
C
gcc -O2 -shared -fPIC -o "$WORK/libshift.so" "$WORK/shift.c"
# the deck, cut as bench/stock_tutorials.py cuts it
(cd "$ROOT" && /usr/bin/python3 -c "
import sys; from pathlib import Path; sys.path.insert(0, 'bench')
import stock_tutorials as s
s.prepare(Path(s.TUTORIALS), '$DECK', Path('$WORK/deck'), $STEPS)")
deck=$(basename "$DECK")

echo "# heap_offset.sh: $DECK, $STEPS steps per run, a=$A b=$B, core $CPU, $(date -u '+%Y-%m-%d %H:%M UTC')" > "$OUT"
echo "# repetition offset binary loop_seconds" >> "$OUT"
for rep in $(seq "$REPS"); do
  for k in $OFFSETS; do
    for name in a b; do
      binary=$A; [ $name = b ] && binary=$B
      rm -rf "$WORK/run"; cp -a "$WORK/deck" "$WORK/run"
      (cd "$WORK/run" && SHIFT_BYTES=$k LD_PRELOAD="$WORK/libshift.so" taskset -c "$CPU" \
         "$binary" -in "$deck" -log none > screen.txt 2>&1)
      t=$(awk '/^Loop time/ {s += $4} END {print s}' "$WORK/run/screen.txt")
      echo "$rep $k $name $t" | tee -a "$OUT"
    done
  done
done
/usr/bin/python3 - "$OUT" <<'PY'
import sys, statistics as st, collections
times = collections.defaultdict(dict)
for line in open(sys.argv[1]):
    if not line.startswith("#"):
        rep, k, name, t = line.split()
        times[int(k), int(rep)][name] = float(t)
print("| heap offset (bytes) | t_b / t_a per repetition | median |")
print("|---|---|---|")
ratios = []
for k in sorted({k for k, _ in times}):
    r = [v["b"] / v["a"] for (kk, _), v in sorted(times.items()) if kk == k]
    ratios += r
    print(f"| {k} | {' '.join(f'{x:.3f}' for x in r)} | {st.median(r):.3f} |")
se = st.stdev(ratios) / len(ratios) ** 0.5
print(f"\nall {len(ratios)}: median {st.median(ratios):.3f}, mean {st.mean(ratios):.3f} ± {se:.3f}")
PY
