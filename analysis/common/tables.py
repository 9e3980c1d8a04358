"""The one reader of our text tables: whitespace-separated columns named
by a `#` comment line (`fix print` / `fix ave/time` records, the records
`fix clog` and the decks append to, the tables the analysis writes).

Rules, the same for every caller:

- the last `#` line before a data line names its columns (a file that runs
  appended to repeats its header: allowed);
- blank lines are skipped; a data line before any header is an error
  naming the file;
- a data line with fewer fields than the header is a line cut by an
  interruption (a run killed while writing): skipped; one with more is an
  error naming the file and line;
- a path ending in .xz is read through lzma (the compressed records of
  doc/data).

Two shapes of the same rows:

    read_table(path)            columns: name -> numpy array of floats
    read_rows(path)             rows: a dict per line, numbers as float
    read_rows(path, text=True)  rows: a dict per line, every value as text
"""

import lzma
from pathlib import Path

import numpy as np


def _parse(path):
    """(the last header's column names, [(names, fields) of each data line])
    of the table at `path`; names is None when the file has no header."""
    names, lines = None, []
    opener = lzma.open if str(path).endswith(".xz") else open
    with opener(path, "rt") as handle:
        for number, line in enumerate(handle, start=1):
            stripped = line.strip()
            if not stripped:
                continue
            if stripped.startswith("#"):
                names = stripped.lstrip("#").split()
                continue
            if names is None:
                raise ValueError(f"{path}: no '#' header line naming the columns")
            fields = stripped.split()
            if len(fields) < len(names):
                continue          # a line cut by an interruption
            if len(fields) > len(names):
                raise ValueError(f"{path}:{number}: {len(fields)} fields, the header names {len(names)}")
            lines.append((names, fields))
    return names, lines


def read_table(path, required=()):
    """The table at `path` as columns: a dict name -> numpy array of floats
    (an empty array per column when the table has a header and no rows).
    Columns of `required` that the table lacks are an error naming the file."""
    names, lines = _parse(path)
    if names is None:
        raise ValueError(f"{path}: no '#' header line naming the columns")
    if any(line_names != names for line_names, _ in lines):
        raise ValueError(f"{path}: its headers name different columns")
    missing = [name for name in required if name not in names]
    if missing:
        raise ValueError(f"{path}: missing columns {missing}")
    data = np.array([[float(value) for value in fields] for _, fields in lines],
                    dtype=float).reshape(len(lines), len(names))
    return {name: data[:, i] for i, name in enumerate(names)}


def read_rows(path, text=False, text_columns=("model",), missing_ok=False):
    """The table at `path` as rows: a list of dicts name -> value, one per
    data line. Values are floats, except those of `text_columns` and any
    that is not a number, which stay text; with `text=True` every value
    stays text (as written, for records compared or rewritten verbatim).
    With `missing_ok`, a file that does not exist (a record no run has
    written yet) has no rows."""
    rows = []
    if missing_ok and not Path(path).exists():
        return rows
    for names, fields in _parse(path)[1]:
        if text:
            rows.append(dict(zip(names, fields)))
            continue
        row = {}
        for name, field in zip(names, fields):
            try:
                row[name] = field if name in text_columns else float(field)
            except ValueError:
                row[name] = field
        rows.append(row)
    return rows
