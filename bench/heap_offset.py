#!/usr/bin/python3
"""Does a tutorial's speed ratio depend on where the heap's chunks fall?
Runs one LIGGGHTS tutorial that needs no other deck first (cut as
bench/stock_tutorials.py cuts it) with two binaries alternately on one
core, each run with the heap shifted by K bytes at start-up: a preloaded
constructor mallocs K bytes and keeps them, so every later chunk sits K
bytes further on. Same code, same allocations, other addresses. Prints one
line per run and a table of t_b / t_a per offset (doc/build.md,
"hydrogel_multicontact: what is left").

A_BINARY defaults to build/bin/liggghts, B_BINARY to Debian's
/usr/bin/liggghts. A run's time is the sum of its `Loop time` lines. Each
run's line `repetition offset binary loop_seconds` (binary a or b) is
appended to bench/results/heap_offset.txt (or --raw NAME) as soon as it is measured, after
a header with the machine, the commit and both binaries; --table FILE
prints the table of such a file (an interrupted one too) without running.
--quick: 20 steps, one repetition, offsets 0 16, output under
bench/work/quick/. About 24 min for the defaults.

    /usr/bin/python3 bench/heap_offset.py                    # 8 offsets, 3 repetitions, 2000 steps
    /usr/bin/python3 bench/heap_offset.py --quick build-other/bin/liggghts   # smoke run, another build as A
    /usr/bin/python3 bench/heap_offset.py --deck cohesion/in.cohesion --offsets 0 64 --repetitions 5
    /usr/bin/python3 bench/heap_offset.py --raw heap_offset_rolled  # a new raw file
    /usr/bin/python3 bench/heap_offset.py --table bench/results/heap_offset.txt
"""

import argparse
import collections
import shutil
import statistics
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import benchlib  # noqa: E402
import stock_tutorials  # noqa: E402

OFFSETS = [0, 16, 48, 112, 240, 496, 1008, 2032]
WORK = benchlib.WORK / "heap_offset"
SHIFT_C = r"""#include <stdlib.h>
__attribute__((constructor)) static void shift(void) {
  const char *s = getenv("SHIFT_BYTES");
  if (s && atoi(s) > 0) { void *volatile p = malloc((size_t)atoi(s)); (void)p; }
}
"""


def table(path):
    """The markdown table of t_b / t_a per offset and per repetition, and a
    summary line, from a raw file (a pair missing its b run is left out)."""
    times = collections.defaultdict(dict)
    for line in Path(path).read_text().splitlines():
        if line.strip() and not line.startswith("#"):
            rep, k, name, t = line.split()
            times[int(k), int(rep)][name] = float(t)
    lines = ["| heap offset (bytes) | t_b / t_a per repetition | median |", "|---|---|---|"]
    ratios = []
    for k in sorted({k for k, _ in times}):
        r = [v["b"] / v["a"] for (kk, _), v in sorted(times.items()) if kk == k and len(v) == 2]
        if r:
            ratios += r
            lines.append(f"| {k} | {' '.join(f'{x:.3f}' for x in r)} | {statistics.median(r):.3f} |")
    if len(ratios) > 1:
        se = statistics.stdev(ratios) / len(ratios) ** 0.5
        lines.append(f"\nall {len(ratios)}: median {statistics.median(ratios):.3f}, "
                     f"mean {statistics.mean(ratios):.3f} ± {se:.3f}")
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     epilog=__doc__.split("\n\n", 1)[1],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("a_binary", nargs="?", type=Path, default=benchlib.OUR_BINARY, metavar="A_BINARY")
    parser.add_argument("b_binary", nargs="?", type=Path, default=benchlib.STOCK_BINARY, metavar="B_BINARY")
    parser.add_argument("--quick", action="store_true",
                        help="smoke run: 20 steps, 1 repetition, offsets 0 16, output under bench/work/quick/")
    parser.add_argument("--deck", default="hydrogel_multicontact/in.hydrogel_multicontact",
                        help="the tutorial deck, relative to the tutorials directory (default: %(default)s)")
    parser.add_argument("--steps", type=int, default=2000, help="at most this many steps per run command")
    parser.add_argument("--repetitions", type=int, default=3)
    parser.add_argument("--offsets", type=int, nargs="+", default=OFFSETS, metavar="K",
                        help="heap offsets in bytes (default: %(default)s)")
    parser.add_argument("--cpu", type=int, default=1, metavar="N", help="the core every run is pinned to")
    parser.add_argument("--raw", default="heap_offset", metavar="NAME",
                        help="the raw file, bench/results/NAME.txt (default: %(default)s): another name "
                             "keeps an earlier measurement that a page quotes")
    parser.add_argument("--table", type=Path, metavar="FILE", help="print the table of a raw file and stop")
    args = parser.parse_args()
    if args.table:
        print(table(args.table))
        return
    if args.quick:
        benchlib.use_smoke_outputs()
        args.steps, args.repetitions, args.offsets = 20, 1, [0, 16]
    binaries = {"a": args.a_binary.absolute(), "b": args.b_binary.absolute()}   # the runs cd
    for binary in binaries.values():
        if not binary.exists():
            sys.exit(f"{binary}: no such binary")
    benchlib.pin_to_cpu(args.cpu)      # gcc and the engines too
    if stock_tutorials.prerequisites(stock_tutorials.TUTORIALS, args.deck):
        sys.exit(f"{args.deck} reads a restart file another deck writes: not supported here")

    WORK.mkdir(parents=True, exist_ok=True)
    (WORK / "shift.c").write_text(SHIFT_C)
    subprocess.run(["gcc", "-O2", "-shared", "-fPIC", "-o", WORK / "libshift.so", WORK / "shift.c"],
                   check=True)
    texts = stock_tutorials.prepare(stock_tutorials.TUTORIALS, args.deck, WORK / "deck", args.steps)
    deck = texts[args.deck][0]

    benchlib.OUR_BINARY = binaries["a"]      # provenance() names it
    header = [f"heap_offset.py: {args.deck}, {args.steps} steps per run, core {args.cpu}"]
    header += [f"{name}: {benchlib.binary_identity(b)}" for name, b in binaries.items()]
    header += benchlib.provenance(load_when="at the start").splitlines()
    header += ["repetition offset binary loop_seconds"]
    raw = benchlib.write_raw(args.raw, "".join(f"# {line}\n" for line in header))
    for rep in range(1, args.repetitions + 1):
        for k in args.offsets:
            for name, binary in binaries.items():
                # a fresh copy each run: the tutorial's meshes and data, none of the last run's output
                run = WORK / "run"
                shutil.rmtree(run, ignore_errors=True)
                shutil.copytree(WORK / "deck", run)
                shifted = {"LD_PRELOAD": str(WORK / "libshift.so"), "SHIFT_BYTES": str(k)}
                result = benchlib.run_deck(deck, run, binary=binary, env=shifted)
                seconds = sum(t for t, _, _ in result["loops"])
                # appended at once: an interrupted bench keeps every run it finished
                with open(raw, "a") as out:
                    out.write(f"{rep} {k} {name} {seconds:.6g}\n")
                benchlib.progress(f"repetition {rep}/{args.repetitions} offset {k} {name} "
                                  f"({benchlib.shown_path(binary)}): {seconds:.6g} s")
    with open(raw, "a") as out:
        out.write(f"# done; load average at the end (1/5/15 min): {benchlib.load_average()}\n")
    benchlib.progress(f"wrote {benchlib.shown_path(raw)}")
    print(table(raw))


if __name__ == "__main__":
    main()
