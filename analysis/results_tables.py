"""The results tables of the scene pages and the README, made from doc/data.

Every number a page gives against a paper comes from a record in doc/data
(doc/data/README.md). Each scene's module `analysis.<scene>.results` has a
function `results_rows(data_dir)` that computes the scene's rows from those
records; this module turns the rows into Markdown tables and puts them into
the pages between two markers:

    <!-- results-table silo2d -->
    ...the table...
    <!-- /results-table -->

The README's table (`<!-- results-table readme -->`) holds the rows each
scene marks as headlines, with a link to the scene's page.

    /usr/bin/python3 -m analysis.results_tables --check   # pages agree with doc/data
    /usr/bin/python3 -m analysis.results_tables --write   # rewrite the tables

tests/test_results_tables.py runs the check, so a table cannot drift from
the records behind it.
"""

import functools
import importlib
import re
import sys
from dataclasses import dataclass
from pathlib import Path
from analysis.common.cli import command_line

ROOT = Path(__file__).resolve().parent.parent
DATA_DIR = ROOT / "doc" / "data"

# scene -> (its rows' module, its page)
SCENES = {
    "silo2d": ("analysis.silo2d.results", "doc/silo2d.md"),
    "pile2d": ("analysis.pile2d.results", "doc/pile2d.md"),
    "silo3d_rotating": ("analysis.silo3d_rotating.results", "doc/silo3d_rotating.md"),
}
README = "README.md"
VERDICTS = ("agrees", "differs", "open")
COLUMNS = ("quantity", "paper", "ours", "window / reading", "verdict")


@dataclass
class Row:
    """One line of a results table.

    quantity: what is compared, with its conditions (e.g. "w_c, model none")
    paper:    the paper's value as the paper gives it (with its uncertainty)
    ours:     our value with its interval, formatted
    window:   the time window, ensemble or reading the value is taken over
    verdict:  "agrees", "differs" (then `cause` says why, shown by runs)
              or "open"
    section:  the page's section (a Markdown anchor, without '#') that
              discusses the row
    headline: also in the README's table
    """
    quantity: str
    paper: str
    ours: str
    window: str
    verdict: str
    section: str
    headline: bool = False
    cause: str = ""

    def __post_init__(self):
        if self.verdict not in VERDICTS:
            raise ValueError(f"verdict {self.verdict!r} is not one of {VERDICTS}")


def markdown_table(rows, page=None):
    """The Markdown table of `rows`; with `page`, verdicts link to it."""
    lines = ["| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    for row in rows:
        target = f"{page}#{row.section}" if page else f"#{row.section}"
        verdict = f"[{row.verdict}]({target})"
        if row.cause:
            verdict += f": {row.cause}"
        cells = (row.quantity, row.paper, row.ours, row.window, verdict)
        lines.append("| " + " | ".join(cell.replace("|", "\\|") for cell in cells) + " |")
    return "\n".join(lines) + "\n"


@functools.lru_cache(maxsize=None)
def scene_rows(scene, data_dir=DATA_DIR):
    """The rows of a scene (computed once per process: some take half a
    minute, from bootstraps over the records)."""
    module_name, _ = SCENES[scene]
    return tuple(importlib.import_module(module_name).results_rows(Path(data_dir)))


def tables(data_dir=DATA_DIR, scenes=None):
    """{marker name: (page path, table text)} for the scenes' pages and,
    when all scenes are asked for, the README."""
    out, headlines = {}, []
    for scene in scenes or SCENES:
        _, page = SCENES[scene]
        rows = scene_rows(scene, data_dir)
        out[scene] = (page, markdown_table(rows))
        # links from the README go to the scene's page (relative to the root)
        headlines += [(row, page) for row in rows if row.headline]
    if scenes:
        return out
    readme_lines = []
    for row, page in headlines:
        readme_lines.append(markdown_table([row], page=page).splitlines()[2])
    header = markdown_table([]).rstrip("\n")
    out["readme"] = (README, header + "\n" + "\n".join(readme_lines) + "\n")
    return out


def _block_pattern(name):
    return re.compile(rf"(<!-- results-table {re.escape(name)} -->\n)(.*?)(<!-- /results-table -->)", re.S)


def replace_block(text, name, table):
    """`text` with the block of marker `name` replaced by `table`;
    raises KeyError when the page has no such block."""
    pattern = _block_pattern(name)
    if not pattern.search(text):
        raise KeyError(f"no '<!-- results-table {name} -->' ... '<!-- /results-table -->' block")
    return pattern.sub(lambda m: m.group(1) + table + m.group(3), text, count=1)


def stale_blocks(root=ROOT, data_dir=DATA_DIR, scenes=None):
    """[(page, marker name)] whose table differs from the records'."""
    stale = []
    for name, (page, table) in tables(data_dir, scenes).items():
        text = (Path(root) / page).read_text()
        if replace_block(text, name, table) != text:
            stale.append((page, name))
    return stale


def write_blocks(root=ROOT, data_dir=DATA_DIR, scenes=None):
    for name, (page, table) in tables(data_dir, scenes).items():
        path = Path(root) / page
        path.write_text(replace_block(path.read_text(), name, table))


def main(argv=None):
    parser = command_line("analysis.results_tables", __doc__.split("\n\n")[0],
                          "/usr/bin/python3 -m analysis.results_tables --check")
    action = parser.add_mutually_exclusive_group(required=True)
    action.add_argument("--check", action="store_true", help="exit 1 naming the tables that differ from doc/data")
    action.add_argument("--write", action="store_true", help="rewrite the tables from doc/data")
    action.add_argument("--print", action="store_true", help="print the tables")
    parser.add_argument("--scene", choices=list(SCENES), action="append",
                        help="only this scene's page (repeatable; the README's table is left as it is)")
    args = parser.parse_args(argv)
    if args.print:
        for name, (page, table) in tables(scenes=args.scene).items():
            print(f"{page} ({name}):\n{table}")
        return 0
    if args.write:
        write_blocks(scenes=args.scene)
        return 0
    stale = stale_blocks(scenes=args.scene)
    for page, name in stale:
        print(f"{page}: the results table '{name}' differs from doc/data "
              f"(/usr/bin/python3 -m analysis.results_tables --write)", file=sys.stderr)
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main())
