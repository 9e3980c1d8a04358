"""Readers for LIGGGHTS text output: `dump custom` / `dump local` files and
`fix print` / `fix ave/time` style tables with a `#` header."""

import numpy as np


def read_dump(path):
    """Frames of a text dump (`dump custom` or `dump local`).

    Returns a list of (step, columns) with columns a dict name -> numpy array,
    rows sorted by `id` when the dump has that column (so that dumps written
    by different numbers of MPI ranks compare row by row)."""
    frames = []
    with open(path) as handle:
        lines = handle.read().splitlines()
    k = 0
    while k < len(lines):
        if not lines[k].startswith("ITEM: TIMESTEP"):
            k += 1
            continue
        step = int(lines[k + 1])
        count = int(lines[k + 3])
        k += 4
        while not lines[k].startswith("ITEM: ATOMS") and not lines[k].startswith("ITEM: ENTRIES"):
            k += 1
        names = lines[k].split()[2:]
        rows = [line.split() for line in lines[k + 1:k + 1 + count]]
        k += 1 + count
        data = np.array(rows, dtype=float).reshape(count, len(names))
        columns = {name: data[:, i] for i, name in enumerate(names)}
        if "id" in columns:
            order = np.argsort(columns["id"], kind="stable")
            columns = {name: values[order] for name, values in columns.items()}
        frames.append((step, columns))
    return frames


def read_table(path):
    """A whitespace-separated table whose last `#` comment line before the
    data names the columns; returns a dict name -> numpy array."""
    names = None
    rows = []
    with open(path) as handle:
        for line in handle:
            stripped = line.strip()
            if not stripped:
                continue
            if stripped.startswith("#"):
                names = stripped.lstrip("#").split()
                continue
            rows.append([float(value) for value in stripped.split()])
    if names is None:
        raise ValueError(f"{path}: no '#' header line naming the columns")
    data = np.array(rows, dtype=float).reshape(len(rows), len(names))
    return {name: data[:, i] for i, name in enumerate(names)}
