"""Test helpers for your own pytest suites (doc/testing.md): run a deck with
silokit's liggghts in a directory of its own, read what it wrote, and compare
dumps and thermo output with a tolerance.

    from analysis.testing import run_deck, assert_dumps_close

    def test_my_deck(tmp_path):
        run = run_deck("decks/in.hopper", tmp_path, variables={"seed": 12345})
        assert_dumps_close(run.path("final.dump"), "reference/final.dump", rtol=1e-8)

The binary is $SILOKIT_LIGGGHTS when set, else build/bin/liggghts of this
repository. numpy only; nothing here imitates the engine: every run is a run
of the built binary.
"""

import os
import shutil
import subprocess
from pathlib import Path

import numpy as np

from analysis.common.lammps_io import iter_dump
from analysis.common.tables import read_table

REPOSITORY = Path(__file__).resolve().parent.parent

__all__ = ["LiggghtsError", "Run", "Frame", "liggghts_binary", "run_deck",
           "read_frames", "read_frame", "read_thermo", "read_record",
           "assert_dumps_close", "assert_thermo_close"]


class LiggghtsError(RuntimeError):
    """LIGGGHTS stopped with an error: str(error) and .message are its first
    ERROR line (or the exit code), .output the whole screen output."""

    def __init__(self, message, output, workdir=None):
        super().__init__(message)
        self.message = message
        self.output = output
        self.workdir = workdir


def liggghts_binary():
    """The liggghts to run: $SILOKIT_LIGGGHTS, else this repository's
    build/bin/liggghts. Debian's liggghts on PATH lacks our styles and is
    never taken."""
    return Path(os.environ.get("SILOKIT_LIGGGHTS", REPOSITORY / "build" / "bin" / "liggghts"))


class Run:
    """What a run left: .workdir, .output (its screen output) and readers
    for the files it wrote there."""

    def __init__(self, workdir, output):
        self.workdir = Path(workdir)
        self.output = output

    def path(self, name):
        """workdir/name; an error naming the files there when it is missing."""
        path = self.workdir / name
        if not path.exists():
            present = sorted(p.name for p in self.workdir.iterdir())
            raise FileNotFoundError(f"the run wrote no {name} in {self.workdir} (it has {present})")
        return path

    def frames(self, name, columns=None):
        return read_frames(self.path(name), columns)

    def frame(self, name, step=None, columns=None):
        return read_frame(self.path(name), step, columns)

    def thermo(self):
        return read_thermo(self.output)

    def record(self, name, required=()):
        return read_record(self.path(name), required)


def run_deck(deck, workdir, nprocs=1, variables=None, files=(), binary=None,
             timeout=600, batch=False, log_file="log.liggghts"):
    """Runs a deck with the built liggghts in `workdir` and returns a Run.

    deck: a deck file (a Path, or a str naming an existing file), copied
    into workdir as in.deck, or the text of a deck (a str with a newline).
    files: more files or directories to copy into workdir (data files,
    meshes, included decks). nprocs > 1 runs under `mpirun -np nprocs`;
    variables become `-var name value`. Raises LiggghtsError with the first
    ERROR line when liggghts fails; a run past `timeout` seconds raises
    subprocess.TimeoutExpired. batch=True runs as a cluster job does: output
    into workdir/out.txt and err.txt, not line-buffered. log_file=None
    leaves out -log (LIGGGHTS then writes log.lammps)."""
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    if isinstance(deck, os.PathLike) or "\n" not in deck:
        deck = Path(deck).read_text()
    (workdir / "in.deck").write_text(deck)
    for item in files:
        item = Path(item)
        if item.is_dir():
            shutil.copytree(item, workdir / item.name, dirs_exist_ok=True)
        else:
            shutil.copy(item, workdir / item.name)

    binary = Path(binary) if binary else liggghts_binary()
    if not binary.exists():
        raise FileNotFoundError(f"{binary} is missing: build it (tools/build.sh) "
                                "or point SILOKIT_LIGGGHTS at a built liggghts")
    command = [str(binary), "-in", "in.deck", "-echo", "screen"]
    if log_file:
        command += ["-log", log_file]
    if not batch:
        # line buffering: the output of a run that hangs or is killed
        command = ["stdbuf", "-oL"] + command
    for name, value in (variables or {}).items():
        command += ["-var", name, str(value)]
    if nprocs > 1:
        command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(nprocs)] + command
    if batch:
        with open(workdir / "out.txt", "w") as out, open(workdir / "err.txt", "w") as err:
            result = subprocess.run(command, cwd=workdir, stdout=out, stderr=err, timeout=timeout)
        output = ((workdir / "out.txt").read_text(errors="replace")
                  + (workdir / "err.txt").read_text(errors="replace"))
    else:
        # errors="replace": on some errors stock LIGGGHTS (error_special.h)
        # prints a line of garbage bytes after the message
        result = subprocess.run(command, cwd=workdir, capture_output=True, text=True,
                                errors="replace", timeout=timeout)
        output = result.stdout + result.stderr
    # lines that start with ERROR: Open MPI's own ORTE_ERROR_LOG lines do not
    errors = [line for line in output.splitlines() if line.startswith("ERROR")]
    if result.returncode != 0 or errors:
        raise LiggghtsError(errors[0] if errors else f"exit code {result.returncode}",
                            output, workdir)
    return Run(workdir, output)


class Frame:
    """One frame of a dump: .step, .source, .columns (name -> numpy array,
    rows sorted by atom id when the dump has an id column)."""

    def __init__(self, step, columns, source=""):
        self.step = step
        self.columns = columns
        self.source = str(source)

    def __getitem__(self, name):
        if name not in self.columns:
            raise KeyError(f"{self.source} step {self.step} has no column {name!r} "
                           f"(it has {list(self.columns)})")
        return self.columns[name]

    def __contains__(self, name):
        return name in self.columns

    def __len__(self):
        return len(next(iter(self.columns.values()))) if self.columns else 0

    @property
    def ids(self):
        return self["id"].astype(np.int64)

    def atom(self, atom_id):
        """name -> value of the atom with this id."""
        where = np.flatnonzero(self.ids == atom_id)
        if where.size == 0:
            raise KeyError(f"{self.source} step {self.step} has no atom id {atom_id}")
        return {name: values[where[0]] for name, values in self.columns.items()}

    def __repr__(self):
        return f"Frame({self.source!r}, step={self.step}, {len(self)} rows, columns={list(self.columns)})"


def _keep(columns, wanted, source, step):
    if wanted is None:
        return columns
    missing = [name for name in wanted if name not in columns]
    if missing:
        raise KeyError(f"{source} step {step} has no column {missing} (it has {list(columns)})")
    keep = ["id"] + [name for name in wanted if name != "id"] if "id" in columns else list(wanted)
    return {name: columns[name] for name in keep}


def read_frames(path, columns=None):
    """The frames of a text dump (`dump custom` / `dump local`) as Frames;
    columns: the names to keep (the id column is always kept)."""
    return [Frame(step, _keep(data, columns, path, step), path) for step, data in iter_dump(path)]


def read_frame(path, step=None, columns=None):
    """One frame of a dump: that of `step`, else the last one."""
    frames = read_frames(path, columns)
    if not frames:
        raise ValueError(f"{path} holds no frame")
    if step is None:
        return frames[-1]
    for frame in frames:
        if frame.step == step:
            return frame
    raise KeyError(f"{path} has no frame at step {step} (it has {[f.step for f in frames]})")


def read_thermo(source):
    """The thermo output of a run: name -> numpy array over every row of
    every `run` (the header line starts with Step; a step printed at the end
    of one run and the start of the next is kept once, the first time).
    The names are LIGGGHTS' headers: for c_ID, f_ID[n] and v_ID the first 8
    characters of ID; a repeated header gets #2, #3 (f_flow[1] f_flow[2]:
    "flow", "flow#2").
    source: the screen output (a str with newlines) or a log file."""
    if isinstance(source, os.PathLike) or "\n" not in source:
        source = Path(source).read_text(errors="replace")
    names, rows, seen = None, [], set()

    def unique(words):
        # LIGGGHTS heads c_ID, f_ID, v_ID columns with the first 8
        # characters of ID alone: f_flow[1] and f_flow[2] both read "flow"
        named = []
        for word in words:
            repeats = named.count(word) + sum(n.startswith(word + "#") for n in named)
            named.append(f"{word}#{repeats + 1}" if repeats else word)
        return named

    header = None
    for line in source.splitlines():
        words = line.split()
        if words[:1] == ["Step"]:
            header = unique(words)
            if names is None:
                names = header
            elif header != names:
                raise ValueError(f"the thermo columns change between runs: {names} then {header}")
            continue
        if header is None:
            continue
        if line.startswith("Loop time"):
            header = None
            continue
        try:
            values = [float(word) for word in words]
        except ValueError:
            continue          # a fix's message or a warning inside the table
        if len(values) == len(header) and values[0] not in seen:
            seen.add(values[0])
            rows.append(values)
    if names is None:
        raise ValueError("no thermo table (no line starting with 'Step')")
    data = np.array(rows, dtype=float).reshape(len(rows), len(names))
    return {name: data[:, k] for k, name in enumerate(names)}


def read_record(path, required=()):
    """One of our records (or any whitespace table whose last '#' line names
    its columns, .xz read as such): name -> numpy array. Columns of
    `required` the table lacks are an error naming the file."""
    return read_table(path, required)


def _as_frames(value):
    if isinstance(value, Frame):
        return [value]
    if isinstance(value, (str, os.PathLike)):
        return read_frames(value)
    return list(value)


def _worst(a, b, rtol, atol):
    """Index of the worst value of b against a and how far past its
    tolerance it is (> 1: out of tolerance); NaN anywhere counts as out."""
    difference = np.abs(a - b)
    allowed = atol + rtol * np.abs(b)
    with np.errstate(divide="ignore", invalid="ignore"):
        excess = np.where(difference <= allowed, 0.0,
                          np.where(allowed > 0, difference / allowed, np.inf))
    excess[np.isnan(a) | np.isnan(b)] = np.inf
    k = int(np.argmax(excess)) if excess.size else 0
    return k, (excess[k] if excess.size else 0.0), int(np.count_nonzero(excess > 1.0))


def _compared_columns(a_names, b_names, columns, key, what_a, what_b):
    if columns is None:
        only_a = [n for n in a_names if n not in b_names]
        only_b = [n for n in b_names if n not in a_names]
        if only_a or only_b:
            raise AssertionError(f"columns differ: {what_a} alone has {only_a}, "
                                 f"{what_b} alone has {only_b}")
        return [n for n in a_names if n != key]
    for name in columns:
        for names, what in ((a_names, what_a), (b_names, what_b)):
            if name not in names:
                raise AssertionError(f"column {name!r} is missing from {what} (it has {list(names)})")
    return [n for n in columns if n != key]


def _check_close(a, b, names, rtol, atol, describe):
    """The worst value over `names`; AssertionError when out of tolerance.
    describe(k) names the row k (an atom id, a step)."""
    worst = None
    out = 0
    for name in names:
        k, excess, count = _worst(np.asarray(a[name], float), np.asarray(b[name], float), rtol, atol)
        out += count
        if count and (worst is None or excess > worst[2]):
            worst = (name, k, excess)
    if worst is None:
        return
    name, k, _ = worst
    va, vb = float(a[name][k]), float(b[name][k])
    raise AssertionError(
        f"{describe(k)}, column {name!r}: {va:.10g} against {vb:.10g} "
        f"(|difference| {abs(va - vb):.3g} > atol + rtol*|b| = {atol + rtol * abs(vb):.3g}); "
        f"{out} value(s) out of tolerance in all")


def assert_dumps_close(a, b, rtol=1e-7, atol=0.0, columns=None):
    """Asserts that dumps a and b agree: a, b are dump files (every frame,
    the steps must match), Frames, or lists of Frames. Atoms are matched by
    id, whatever their order; columns: the names to compare (default all,
    and both must have the same). A value passes when |a - b| <= atol +
    rtol*|b|; NaN never passes. The AssertionError names the step, the
    worst atom id and column, both values, and how many are out."""
    frames_a, frames_b = _as_frames(a), _as_frames(b)
    steps_a, steps_b = [f.step for f in frames_a], [f.step for f in frames_b]
    if steps_a != steps_b:
        raise AssertionError(f"the dumps hold other steps: a {steps_a}, b {steps_b} "
                             "(read_frame(path, step) picks one frame)")
    for fa, fb in zip(frames_a, frames_b):
        what_a, what_b = f"a ({fa.source} step {fa.step})", f"b ({fb.source} step {fb.step})"
        for frame, what in ((fa, what_a), (fb, what_b)):
            if "id" not in frame:
                raise AssertionError(f"{what} has no id column: atoms cannot be matched")
        names = _compared_columns(list(fa.columns), list(fb.columns), columns, "id", what_a, what_b)
        ids_a, ids_b = fa.ids, fb.ids
        for ids, other, what, other_what in ((ids_a, ids_b, what_a, what_b), (ids_b, ids_a, what_b, what_a)):
            alone = np.setdiff1d(ids, other)
            if alone.size:
                raise AssertionError(f"atom id {alone[0]} is in {what} but not in {other_what} "
                                     f"({alone.size} such atom(s): {alone[:10].tolist()})")
        # both sorted by id by the reader, but Frames may be made by hand
        order_a, order_b = np.argsort(ids_a, kind="stable"), np.argsort(ids_b, kind="stable")
        rows_a = {n: np.asarray(fa.columns[n], float)[order_a] for n in names}
        rows_b = {n: np.asarray(fb.columns[n], float)[order_b] for n in names}
        sorted_ids = ids_a[order_a]
        _check_close(rows_a, rows_b, names, rtol, atol,
                     lambda k: f"dumps differ at step {fa.step}: worst atom id {sorted_ids[k]}")


def assert_thermo_close(a, b, rtol=1e-7, atol=0.0, columns=None):
    """Asserts that two thermo tables agree at the same steps: a, b are
    what read_thermo returned, screen outputs or log files. Rows are
    matched by Step; columns as in assert_dumps_close. The AssertionError
    names the worst step and column."""
    table_a = a if isinstance(a, dict) else read_thermo(a)
    table_b = b if isinstance(b, dict) else read_thermo(b)
    names = _compared_columns(list(table_a), list(table_b), columns, "Step", "a", "b")
    steps_a, steps_b = table_a["Step"], table_b["Step"]
    if not np.array_equal(np.sort(steps_a), np.sort(steps_b)):
        only_a = np.setdiff1d(steps_a, steps_b)
        only_b = np.setdiff1d(steps_b, steps_a)
        raise AssertionError(f"the thermo tables have other steps: a alone {only_a[:10].tolist()}, "
                             f"b alone {only_b[:10].tolist()}")
    order_a, order_b = np.argsort(steps_a, kind="stable"), np.argsort(steps_b, kind="stable")
    rows_a = {n: np.asarray(table_a[n], float)[order_a] for n in names}
    rows_b = {n: np.asarray(table_b[n], float)[order_b] for n in names}
    steps = steps_a[order_a]
    _check_close(rows_a, rows_b, names, rtol, atol,
                 lambda k: f"thermo differs: worst step {int(steps[k])}")
