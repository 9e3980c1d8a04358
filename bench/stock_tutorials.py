#!/usr/bin/python3
"""Is our build as fast as Debian's /usr/bin/liggghts on LIGGGHTS' own
tutorials? Runs every tutorial deck of Debian's liggghts-doc package with
our binary and Debian's, alternately, repeated, and tables per deck: did it
finish in both, are the thermo lines identical, t_debian / t_ours, and did
ours take LIGGGHTS' generic (unspecialised) contact-model path.

Decks: every file `in.*` with a `run` command under the tutorials directory
(default /usr/share/doc/liggghts/examples/LIGGGHTS/Tutorials_public, from
`apt-get install liggghts-doc`). A deck that reads a restart file written by
another deck of its directory (`read_restart` / `write_restart`) runs that
deck first, untimed, with the same binary.

Shortening, the same text for every binary: each `run N` becomes at most
--steps steps (`run N upto`: at most --steps steps, never past step N), and
a loop (`variable v loop N` ... `next v`) runs at most --steps steps in
all. Everything else in the deck (its dumps included) is left as it is.
Each change is listed in the report.

Binaries: `--binary NAME=PATH` (repeatable; default: ours =
build/bin/liggghts), plus Debian's /usr/bin/liggghts as "debian". The order
of the binaries rotates from one repetition to the next. A deck that fails
with a binary is not run again with it.

Times: the `Loop time` lines of a run summed (the timed deck only), and the
CPU time of the LIGGGHTS process (start-up and set-up included). The ratio
t_debian / t_ours is taken within each repetition; above 1 ours is faster.

Instructions (`--instructions`, instead of the times): each deck once per
binary under valgrind's callgrind, I_debian / I_ours of the instructions
the timed deck executes (start-up included; its prerequisites run
uncounted). A count does not depend on the machine's load, where the times
on a shared machine spread by ±15 % and more; it does not see cache misses
or branch mispredictions. About 50 times slower than a run: give it a
small --steps.

The page has two sections, "times" and "instructions"; each run rewrites
its own and leaves the other as it is. `--section NAME` writes a section of
its own instead (a few decks measured again, beside the full tables).
`--cpu N` runs every binary on core N: on a machine shared with a
campaign, pin the campaign to the other core, and the binaries compare on
a core nothing else of ours is scheduled onto.

Generic path: LIGGGHTS warns "The contact model you specified is not located
in any whitelist" for each pair style or wall whose contact-model
combination was not specialised at build time. The table counts these
warnings in each binary's output and names the deck's combinations that
are missing from the binary's compiled list (style_contact_model.h of its
build tree, build/liggghts/src/ for ours), in the GRAN_MODEL(...) spelling
of src_plugin/liggghts/style_contact_model_user.whitelist. (LIGGGHTS' warning does
not name the combination.)

Writes its section of doc/speed_stock_tutorials.md and the raw numbers in
bench/results/stock_tutorials.txt (another section's:
stock_tutorials_<section>.txt); with --quick, under bench/work/quick/.

    /usr/bin/python3 bench/stock_tutorials.py                       # every deck, 5 repetitions
    /usr/bin/python3 bench/stock_tutorials.py --decks cohesion packing --repetitions 9
    /usr/bin/python3 bench/stock_tutorials.py --decks hysteresis --binary ours=build/bin/liggghts \\
        --binary o3=build-o3/bin/liggghts --steps 20000
    /usr/bin/python3 bench/stock_tutorials.py --instructions --steps 500 --decks sph_1 hydrogel_multicontact
    /usr/bin/python3 bench/stock_tutorials.py --decks sph_1 mesh_tet --cpu 1 --section again --repetitions 9
    /usr/bin/python3 bench/stock_tutorials.py --quick               # smoke run, ~1 min
"""

import argparse
import re
import shutil
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import benchlib  # noqa: E402
import callgrind  # noqa: E402
from stock_speed import DEBIAN, cell, existing_binaries  # noqa: E402

TUTORIALS = Path("/usr/share/doc/liggghts/examples/LIGGGHTS/Tutorials_public")
WHITELIST_WARNING = "not located in any whitelist"
PAGE = "speed_stock_tutorials.md"
PAGE_HEADER = """# Speed on LIGGGHTS' own tutorials: our build against Debian's

Written by `bench/stock_tutorials.py` (see `bench/README.md`); do not edit by
hand. Two sections: the times of repeated, alternating runs, and the
instructions each binary executes on the same decks (`--instructions`).
"""


# --- the decks -----------------------------------------------------------

def find_decks(root):
    """Relative paths of the files in.* under `root` that contain a `run`
    command (an included parameter file or a ParScale input has none)."""
    found = []
    for path in sorted(root.rglob("in.*")):
        if path.is_file() and any(command(line)[:1] == ["run"]
                                  for line in path.read_text(errors="replace").splitlines()):
            found.append(path.relative_to(root).as_posix())
    return found


def command(line):
    """The words of one deck line without its comment."""
    return line.split("#", 1)[0].split()


def select(decks, wanted):
    """--decks: a deck's path (cohesion/in.cohesion), its directory
    (cohesion: every deck in it) or its file name (in.cohesion)."""
    if not wanted:
        return decks
    chosen = []
    for want in wanted:
        want = want.strip("/")
        hits = [d for d in decks if d == want or d.startswith(want + "/")
                or Path(d).name == want]
        if not hits:
            sys.exit(f"--decks {want}: no such tutorial deck; there are: " + ", ".join(decks))
        chosen += [d for d in hits if d not in chosen]
    return chosen


def prerequisites(root, deck):
    """The decks of the same directory that write the restart files `deck`
    reads, in the order they must run."""
    directory = (root / deck).parent
    needed = []
    for line in (root / deck).read_text(errors="replace").splitlines():
        words = command(line)
        if words[:1] == ["read_restart"] and len(words) > 1:
            for other in sorted(directory.glob("in.*")):
                other_name = other.relative_to(root).as_posix()
                if other_name == deck or other_name in needed:
                    continue
                if any(command(l)[:2] == ["write_restart", words[1]]
                       for l in other.read_text(errors="replace").splitlines()):
                    needed.append(other_name)
    return needed


RUN = re.compile(r"^(\s*)run\s+(\S+)(.*)$")
LOOP = re.compile(r"^(\s*)variable\s+(\S+)\s+loop\s+(\d+)(\s*(#.*)?)$")


def shorten(text, steps):
    """The deck with every run capped at `steps` steps and every loop at
    `steps` steps in all; returns (text, changes), a change being
    (line number, old line, what it became)."""
    lines = text.splitlines()
    out, changes = [], []
    for number, line in enumerate(lines, 1):
        loop = LOOP.match(line)
        run = RUN.match(line.split("#", 1)[0])
        if loop:
            indent, name, count = loop.group(1), loop.group(2), int(loop.group(3))
            chunk = loop_steps(lines[number:], name)
            capped = max(1, steps // chunk)
            if capped < count:
                out.append(f"{indent}variable {name} loop {capped}")
                changes.append((number, line.strip(),
                                f"{capped} passes ({chunk} step{'s' if chunk > 1 else ''} each)"))
                continue
        elif run:
            indent, count, rest = run.groups()
            words = rest.split()
            upto = "upto" in words
            options = " ".join(w for w in words if w != "upto")
            # LIGGGHTS' formulas have no min()/max() of two numbers:
            # min(left, steps) for left >= 0 by comparisons, 0 below
            left, variable = f"silokit_left_{number}", f"silokit_run_{number}"
            if upto:
                shown = f"at most {steps} steps, not past step {count}"
            else:
                shown = f"at most {steps} steps"
            if upto or not count.isdigit() or int(count) > steps:
                out.append(f"{indent}variable {left} equal {count}" + ("-step" if upto else ""))
                out.append(f'{indent}variable {variable} equal "v_{left}*(v_{left}>0)*(v_{left}<={steps})'
                           f'+{steps}*(v_{left}>{steps})"')
                out.append(f"{indent}run ${{{variable}}} {options}".rstrip())
                changes.append((number, line.strip(), shown))
                continue
        out.append(line)
    return "\n".join(out) + "\n", changes


def loop_steps(following, name):
    """Steps of one pass of loop `name`: the runs before its `next`
    (a run count that is not a plain number counts as 1)."""
    total = 0
    for line in following:
        words = command(line)
        if words[:2] == ["next", name]:
            break
        if words[:1] == ["run"] and len(words) > 1:
            total += int(words[1]) if words[1].isdigit() else 1
    return max(total, 1)


# --- contact-model combinations ---------------------------------------------

KINDS = ("NORMAL", "TANGENTIAL", "COHESION", "ROLLING", "SURFACE")
KEYWORDS = {"model": "NORMAL", "tangential": "TANGENTIAL", "cohesion": "COHESION",
            "rolling_friction": "ROLLING", "surface": "SURFACE"}
DEFAULTS = {"TANGENTIAL": "TANGENTIAL_NO_HISTORY", "COHESION": "COHESION_OFF",
            "ROLLING": "ROLLING_OFF", "SURFACE": "SURFACE_DEFAULT"}
MODEL_MACRO = re.compile(r"^\s*(NORMAL|TANGENTIAL|COHESION|ROLLING|SURFACE)_MODEL\(\s*(\w+)\s*,"
                         r"\s*([\w/]+)\s*,\s*\d+\s*\)", re.MULTILINE)
GRAN_MODEL = re.compile(r"^\s*GRAN_MODEL\(([^)]*)\)", re.MULTILINE)


def source_tree(binary):
    """The LIGGGHTS source tree a binary of ours was built from
    (bin/../liggghts/src), or None (Debian's binary, a copy elsewhere)."""
    src = Path(binary).resolve().parent.parent / "liggghts" / "src"
    return src if (src / "style_contact_model.h").exists() else None


def model_names(src):
    """{(kind, deck keyword): enum name} from the *_MODEL(...) lines of the
    sub-model headers."""
    names = {}
    if src is None:
        return names
    for header in src.glob("*_model_*.h"):
        for kind, enum, keyword in MODEL_MACRO.findall(header.read_text(errors="replace")):
            names[(kind, keyword)] = enum
    return names


def compiled(src):
    """The combinations specialised in a build: GRAN_MODEL lines of its
    style_contact_model.h, as tuples of five names."""
    if src is None:
        return None
    text = (src / "style_contact_model.h").read_text(errors="replace")
    return {tuple(p.strip() for p in args.split(",")) for args in GRAN_MODEL.findall(text)}


def combinations(text, names):
    """The contact-model combinations of a deck's `pair_style gran` and
    `fix ... wall/gran` commands, as GRAN_MODEL(...) argument tuples
    (normal, tangential, cohesion, rolling, surface)."""
    joined = re.sub(r"&\s*\n", " ", text)
    found = []
    for line in joined.splitlines():
        words = command(line)
        is_pair = words[:2] == ["pair_style", "gran"]
        is_wall = len(words) > 3 and words[0] == "fix" and words[3].startswith("wall/gran")
        if not (is_pair or is_wall) or "model" not in words:
            continue
        chosen = dict(DEFAULTS)
        for i, word in enumerate(words[:-1]):
            if word in KEYWORDS:
                kind = KEYWORDS[word]
                keyword = words[i + 1]
                chosen[kind] = names.get((kind, keyword),
                                         f"{kind}_{keyword.upper().replace('/', '_')}"
                                         if kind != "NORMAL" else keyword.upper().replace("/", "_"))
        combination = tuple(chosen[k] for k in KINDS)
        if combination not in found:
            found.append(combination)
    return found


def gran_model(combination):
    return "GRAN_MODEL(" + ", ".join(combination) + ")"


# --- running ---------------------------------------------------------------

def prepare(root, deck, workdir, steps):
    """A fresh copy of the deck's directory in workdir, its decks shortened
    (written under their own names too: a deck may `jump` to itself by
    name); returns {deck: (text, changes)}."""
    if workdir.exists():
        shutil.rmtree(workdir)
    shutil.copytree((root / deck).parent, workdir)
    texts = {}
    for name in prerequisites(root, deck) + [deck]:
        text, changes = shorten((root / name).read_text(errors="replace"), steps)
        (workdir / Path(name).name).write_text(text)
        texts[name] = (text, changes)
    return texts


def failure_reason(problem):
    """The ERROR line of a failed run (or its exit code), short."""
    text = str(problem)
    errors = [l[l.index("ERROR"):].strip() for l in text.splitlines() if "ERROR" in l]
    reason = errors[0] if errors else text.splitlines()[0].split(": ", 1)[-1]
    reason = re.sub(r"\s*\(\S+\.cpp:\d+\)", "", reason)
    return reason[:160]


def thermo_rows(output):
    """Thermo lines: (step, values) after each `Step ...` header, without
    the CPU column (time, not state)."""
    rows, header = [], None
    for line in output.splitlines():
        words = line.split()
        if words[:1] == ["Step"]:
            header = words
            continue
        if header and words and words[0].isdigit() and len(words) == len(header):
            values = tuple(w for h, w in zip(header[1:], words[1:]) if h != "CPU")
            rows.append((int(words[0]), values))
        elif header and line.startswith("Loop time"):
            header = None
    return rows


def first_difference(a, b):
    """None if the two thermo series agree, else a short description: the
    first step where they differ and the largest relative difference of
    that line (or which one is longer)."""
    for (step_a, values_a), (step_b, values_b) in zip(a, b):
        if (step_a, values_a) == (step_b, values_b):
            continue
        if step_a != step_b:
            return f"steps differ from step {min(step_a, step_b)}"
        worst = 0.0
        for x, y in zip(values_a, values_b):
            try:
                x, y = float(x), float(y)
            except ValueError:
                worst = float("inf")
                continue
            if x != y:
                worst = max(worst, abs(x - y) / max(abs(x), abs(y)))
        return f"from step {step_a}, relative difference {worst:.2g}"
    if len(a) != len(b):
        return f"one prints {len(a)} thermo lines, the other {len(b)}"
    return None


def run_one(root, deck, name, binary, workdir, steps, counted=False):
    """Runs `deck` (after its prerequisites) with one binary; returns a
    dict: ok, reason, loop (s), cpu (s), steps, atoms, thermo, warnings,
    and with `counted` (under callgrind) instructions."""
    texts = prepare(root, deck, workdir, steps)
    try:
        for before in prerequisites(root, deck):
            benchlib.run_deck(texts[before][0], workdir, binary=binary)
        if counted:
            result = callgrind.run_counted(texts[deck][0], workdir, binary)
            result["loops"] = benchlib.loop_lines(result["output"])
        else:
            result = benchlib.run_deck(texts[deck][0], workdir, binary=binary)
    except benchlib.LiggghtsFailed as problem:
        return {"ok": False, "reason": failure_reason(problem)}
    loops = result["loops"]
    return {"ok": True, "loop": sum(t for t, _, _ in loops), "cpu": result["cpu"],
            "steps": sum(s for _, s, _ in loops), "atoms": loops[-1][2] if loops else 0,
            "thermo": thermo_rows(result["output"]),
            "warnings": result["output"].count(WHITELIST_WARNING),
            "instructions": result.get("instructions")}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     epilog=__doc__.split("\n\n")[-1],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true",
                        help="smoke run: 100 steps per run, 1 repetition, outputs under bench/work/quick/")
    parser.add_argument("--binary", action="append", metavar="NAME=PATH",
                        help="a LIGGGHTS binary of ours (repeatable; the generic-path column is "
                             "the first's); default: ours=build/bin/liggghts")
    parser.add_argument("--decks", nargs="+", metavar="DECK",
                        help="only these decks: path (cohesion/in.cohesion), directory (cohesion) "
                             "or file name (in.cohesion); default: all")
    parser.add_argument("--tutorials", type=Path, default=TUTORIALS,
                        help=f"the tutorials directory (default: {TUTORIALS})")
    parser.add_argument("--repetitions", type=int, default=5)
    parser.add_argument("--steps", type=int, default=5000,
                        help="at most this many steps per run command (and per loop)")
    parser.add_argument("--section", metavar="NAME",
                        help="the page's section to write [times, or instructions]: another name keeps "
                             "the full tables and adds this run's (e.g. a few decks measured again)")
    parser.add_argument("--cpu", type=int, metavar="N",
                        help="run every binary on core N only (os.sched_setaffinity), so that the "
                             "binaries share one core and nothing else is scheduled onto it by us")
    parser.add_argument("--instructions", action="store_true",
                        help="count instructions under callgrind instead of timing: one run per deck and "
                             "binary, the page's 'instructions' section")
    args = parser.parse_args()
    if args.quick:
        benchlib.use_smoke_outputs()
        args.repetitions, args.steps = 1, 100
    if args.instructions:
        args.repetitions = 1
        if not shutil.which("valgrind"):
            sys.exit("--instructions needs valgrind (apt-get install valgrind)")
    if args.repetitions < 1 or args.steps < 1:
        sys.exit("--repetitions and --steps must be at least 1")
    if args.section is not None and not re.fullmatch(r"[a-z0-9_]+", args.section):
        sys.exit(f"--section {args.section!r}: lower-case letters, digits and _ only")
    if args.cpu is not None:
        benchlib.pin_to_cpu(args.cpu)
    if not args.tutorials.is_dir():
        sys.exit(f"{args.tutorials}: no such directory (apt-get install liggghts-doc)")

    binaries = existing_binaries(args.binary)
    names = list(binaries)
    ours = names[0]
    benchlib.OUR_BINARY = binaries[ours]
    decks = select(find_decks(args.tutorials), args.decks)
    start_load = benchlib.load_average()
    work = benchlib.WORK / ("quick" if args.quick else "") / "stock_tutorials"

    results = {(d, n): [] for d in decks for n in names}
    failed = {}
    raw = ["# stock_tutorials raw results", "# binaries: " + ", ".join(
        f"{n} {benchlib.binary_identity(binaries[n])}" for n in names),
        f"# tutorials {args.tutorials}, at most {args.steps} steps per run",
        "# repetition deck binary loop_time_s steps atoms process_cpu_s whitelist_warnings"
    + (" instructions" if args.instructions else "")]
    for rep in range(args.repetitions):
        order = names[rep % len(names):] + names[:rep % len(names)]
        for deck in decks:
            for name in order:
                if (deck, name) in failed:
                    continue
                workdir = work / deck.replace("/", "_") / name
                outcome = run_one(args.tutorials, deck, name, binaries[name], workdir, args.steps,
                                  args.instructions)
                if not outcome["ok"]:
                    failed[(deck, name)] = outcome["reason"]
                    raw.append(f"{rep} {deck} {name} failed: {outcome['reason']}")
                    benchlib.progress(f"repetition {rep + 1}/{args.repetitions} {deck} {name}: "
                                      f"failed: {outcome['reason']}")
                    continue
                results[(deck, name)].append(outcome)
                counted = f" {outcome['instructions']}" if args.instructions else ""
                raw.append(f"{rep} {deck} {name} {outcome['loop']:.6g} {outcome['steps']} "
                           f"{outcome['atoms']} {outcome['cpu']:.4g} {outcome['warnings']}{counted}")
                benchlib.progress(f"repetition {rep + 1}/{args.repetitions} {deck} {name}: loop time "
                                  f"{outcome['loop']:.4g} s, {outcome['steps']} steps, "
                                  f"{outcome['atoms']} atoms, {outcome['warnings']} whitelist warnings"
                                  + (f", {outcome['instructions']:.4e} instructions" if counted else ""))

    section = args.section or ("instructions" if args.instructions else "times")
    page = (instructions_report if args.instructions else report)(
        args, decks, names, binaries, results, failed, start_load)
    page_path = (benchlib.WORK / "quick" if args.quick else benchlib.ROOT / "doc") / PAGE
    benchlib.write_page_section(page_path, section, page, PAGE_HEADER)
    path = benchlib.write_raw("stock_tutorials" + ("" if section == "times" else f"_{section}"),
                              "\n".join(raw) + "\n\n" + page)
    benchlib.progress(f"wrote {page_path.relative_to(benchlib.ROOT)} and "
                      f"{path.relative_to(benchlib.ROOT)}")
    print(page)


def report(args, decks, names, binaries, results, failed, start_load):
    ours = names[0]
    builds = [n for n in names if n != DEBIAN]
    src = source_tree(binaries[ours])
    specialised, enum_names = compiled(src), model_names(src)
    lines = [
        "## Times" + (f" (`--section {args.section}`)" if args.section else ""),
        "",
        f"Each tutorial deck of Debian's `liggghts-doc` ({args.tutorials}) runs with "
        + ", ".join(f"**{n}** {benchlib.binary_identity(binaries[n])}" for n in names)
        + f", alternately (the order rotates){pinned(args)}, {args.repetitions} repetition"
        + ("s" if args.repetitions > 1 else "") + f"; every `run` is cut to at most {args.steps} "
        "steps, the same deck text for every binary (changes listed below).",
        "",
        "Ratios t_debian / t_build per repetition, median [min–max]; above 1 the build is faster. "
        "Loop: the deck's `Loop time` lines summed; CPU: the process's user + system time, "
        "start-up included. Generic path: LIGGGHTS' warning that the contact model is "
        f"\"{WHITELIST_WARNING}\" in {ours}'s output (count), and the deck's combinations "
        f"missing from {ours}'s compiled list.",
        "",
        "| deck | atoms | steps | finished in " + ("both" if len(names) == 2 else "all")
        + " | thermo | " + " | ".join(f"loop t_debian / t_{n} | CPU t_debian / t_{n}" for n in builds)
        + f" | generic path in {ours} |",
        "|---|---|---|---|---|" + "---|---|" * len(builds) + "---|",
    ]
    missing_all = {}
    for deck in decks:
        mine, theirs = results[(deck, ours)], results[(deck, DEBIAN)]
        why = [f"{n}: {failed[(deck, n)]}" for n in names if (deck, n) in failed]
        finished = "yes" if not why else "no (" + "; ".join(why) + ")"
        thermo, ratios = "—", []
        if theirs:
            differences = {n: first_difference(results[(deck, n)][0]["thermo"], theirs[0]["thermo"])
                           for n in builds if results[(deck, n)]}
            if differences and not any(differences.values()):
                thermo = "identical"
            elif differences:
                thermo = "; ".join(f"{n}: {d or 'identical'}" for n, d in differences.items())
            unsteady = [n for n in names if any(
                first_difference(r["thermo"], results[(deck, n)][0]["thermo"])
                for r in results[(deck, n)][1:])]
            if unsteady:
                thermo += "; varies between repetitions of " + ", ".join(unsteady)
        for n in builds:
            pairs = list(zip(results[(deck, n)], theirs))
            ratios.append(cell([b["loop"] / a["loop"] for a, b in pairs if a["loop"] > 0]))
            ratios.append(cell([b["cpu"] / a["cpu"] for a, b in pairs]))
        text = (Path(args.tutorials) / deck).read_text(errors="replace")
        combos = combinations(text, enum_names)
        # a deck ours cannot run (a style it lacks) needs no specialisation
        missing = [c for c in combos
                   if mine and specialised is not None and c not in specialised]
        for c in missing:
            missing_all.setdefault(c, []).append(deck)
        warnings = mine[0]["warnings"] if mine else None
        generic = "—" if warnings is None else ("yes" if warnings else "no")
        if warnings:
            generic += f" ({warnings} warning{'s' if warnings > 1 else ''})"
        if missing:
            generic += ": " + ", ".join(gran_model(c) for c in missing)
        elif warnings:
            generic += ": combination not identified from the deck"
        if theirs and theirs[0]["warnings"]:
            generic += f"; Debian's binary warns too ({theirs[0]['warnings']})"
        sample = mine or theirs
        atoms = str(sample[0]["atoms"]) if sample else "—"
        steps = str(sample[0]["steps"]) if sample else "—"
        lines.append(f"| {deck} | {atoms} | {steps} | {finished} | {thermo} | "
                     + " | ".join(ratios) + f" | {generic} |")
    lines += ["", "### Contact-model combinations not specialised in " + ours, ""]
    if specialised is None:
        lines.append(f"Unknown: no LIGGGHTS source tree next to {binaries[ours]}.")
    elif not missing_all:
        lines.append("None: every combination the decks use is in the compiled list.")
    else:
        lines.append("Line to add to `src_plugin/liggghts/style_contact_model_user.whitelist` to "
                     "specialise one, and the decks that use it:")
        lines.append("")
        lines += [f"- `{gran_model(c)}`: " + ", ".join(ds) for c, ds in missing_all.items()]
    lines += ["", "### How the decks were shortened", ""] + shortening(args, decks)
    lines += ["", benchlib.provenance(extra_load=start_load), ""]
    return "\n".join(lines)


def pinned(args):
    return f", all on core {args.cpu} (--cpu)" if args.cpu is not None else ""


def shortening(args, decks):
    """One markdown line per deck (and prerequisite): its changed lines."""
    lines = []
    for deck in decks:
        directory = Path(args.tutorials)
        for name in prerequisites(directory, deck) + [deck]:
            _, changes = shorten((directory / name).read_text(errors="replace"), args.steps)
            label = name + (f" (run first, untimed, for {deck})" if name != deck else "")
            if changes:
                lines.append(f"- {label}: " + "; ".join(
                    f"line {n} `{old}` → {new}" for n, old, new in changes))
            else:
                lines.append(f"- {label}: unchanged")
    return lines


def instructions_report(args, decks, names, binaries, results, failed, start_load):
    """The 'instructions' section: per deck the instructions each binary
    executed and I_debian / I_build (above 1 the build executes fewer)."""
    builds = [n for n in names if n != DEBIAN]
    lines = [
        "## Instructions" + (f" (`--section {args.section}`)" if args.section else ""),
        "",
        "Each deck once per binary under valgrind's callgrind ("
        + ", ".join(f"**{n}** {benchlib.binary_identity(binaries[n])}" for n in names)
        + f"); every `run` cut to at most {args.steps} steps, the same deck text for every binary. "
        "Instructions of the whole process (start-up and set-up included; a deck's prerequisite "
        "runs uncounted); I_debian / I_build above 1: the build executes fewer. Counts do not "
        "depend on the machine's load; they do not see cache misses or branch mispredictions.",
        "",
        "| deck | atoms | steps | thermo | " + " | ".join(f"I_{n} (10⁹)" for n in names) + " | "
        + " | ".join(f"I_debian / I_{n}" for n in builds) + " |",
        "|---|---|---|---|" + "---|" * (len(names) + len(builds)),
    ]
    for deck in decks:
        why = [f"{n}: {failed[(deck, n)]}" for n in names if (deck, n) in failed]
        if why:
            lines.append(f"| {deck} | — | — | failed ({'; '.join(why)}) |" + " — |" * (len(names) + len(builds)))
            continue
        runs = {n: results[(deck, n)][0] for n in names}
        differences = [n for n in builds if first_difference(runs[n]["thermo"], runs[DEBIAN]["thermo"])]
        thermo = "identical" if not differences else "differs in " + ", ".join(differences)
        counts = {n: runs[n]["instructions"] for n in names}
        lines.append(f"| {deck} | {runs[DEBIAN]['atoms']} | {runs[DEBIAN]['steps']} | {thermo} | "
                     + " | ".join(f"{counts[n] / 1e9:.3f}" for n in names) + " | "
                     + " | ".join(f"{counts[DEBIAN] / counts[n]:.4f}" for n in builds) + " |")
    lines += ["", "### How the decks were shortened", ""] + shortening(args, decks)
    lines += ["", benchlib.provenance(extra_load=start_load), ""]
    return "\n".join(lines)


if __name__ == "__main__":
    main()
