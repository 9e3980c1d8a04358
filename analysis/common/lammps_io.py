"""Readers for LIGGGHTS text output: `dump custom` / `dump local` files
and the thermo table of a run's screen output. Tables with a `#` header
(`fix print`, `fix ave/time`, our records) are read by analysis.common.tables."""

import itertools

import numpy as np


def read_dump(path):
    """Frames of a text dump (`dump custom` or `dump local`).

    Returns a list of (step, columns) with columns a dict name -> numpy array,
    rows sorted by `id` when the dump has that column (so that dumps written
    by different numbers of MPI ranks compare row by row)."""
    return list(iter_dump(path))


def _frame_header(handle):
    """(step, count, column names) of the next frame, None at the end."""
    for line in handle:
        if line.startswith("ITEM: TIMESTEP"):
            break
    else:
        return None
    step = int(handle.readline())
    handle.readline()
    count = int(handle.readline())
    line = handle.readline()
    while not line.startswith(("ITEM: ATOMS", "ITEM: ENTRIES")):
        line = handle.readline()
    return step, count, line.split()[2:]


def iter_dump(path, wanted=None):
    """Frames of a `dump custom` / `dump local` text file one at a time, as
    (step, columns) with columns a dict name -> numpy array (rows sorted by
    id when there is an id column), without holding the file in memory;
    frames whose step fails `wanted(step)` are skipped unparsed."""
    with open(path) as handle:
        while (header := _frame_header(handle)) is not None:
            step, count, names = header
            rows = list(itertools.islice(handle, count))
            if wanted is not None and not wanted(step):
                continue
            data = np.array(" ".join(rows).split(), dtype=float).reshape(count, len(names))
            columns = {name: data[:, k] for k, name in enumerate(names)}
            if "id" in columns:
                order = np.argsort(columns["id"], kind="stable")
                columns = {name: values[order] for name, values in columns.items()}
            yield step, columns


def dump_steps(path):
    """Steps of the frames of a dump, reading only the headers' numbers."""
    steps = []
    with open(path) as handle:
        while (header := _frame_header(handle)) is not None:
            steps.append(header[0])
            for _ in itertools.islice(handle, header[1]):
                pass
    return np.array(steps, dtype=np.int64)


def thermo_rows(output, columns):
    """step -> the other values of each thermo line with `columns` numbers
    (Step first) in a run's screen output; lines that are not all numbers
    inside a table (a fix's messages, warnings) are skipped, and a table
    ends at its `Loop time` line."""
    rows, inside = {}, False
    for line in output.splitlines():
        words = line.split()
        if words[:2] == ["Step", "Atoms"]:
            inside = True
            continue
        if inside:
            try:
                values = [float(w) for w in words]
            except ValueError:
                inside = not line.startswith("Loop time")
                continue
            if len(values) == columns:
                rows[int(values[0])] = values[1:]
    return rows
