"""doc/data stays lean (doc/data/README.md, "Size"): under 30 MB in the
tree, and no dump, restart or checkpoint of a run in it but the inputs
its README lists as kept."""

import fnmatch
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT / "doc" / "data"
LIMIT = 30_000_000                      # bytes: the design rule's 30 MB
RUN_STATE = ("dump*", "*.restart", "*.restart.*", "*restart*", "checkpoint*", "state*.restart*")
KEPT_INPUTS = "## Kept inputs"


def files(directory):
    return [path for path in directory.rglob("*") if path.is_file()]


def size_problem(directory, limit=LIMIT, largest=5):
    """None, or a message with the total and the `largest` files by size."""
    found = files(directory)
    total = sum(path.stat().st_size for path in found)
    if total <= limit:
        return None
    biggest = sorted(found, key=lambda path: path.stat().st_size, reverse=True)[:largest]
    return (f"{directory} holds {total / 1e6:.1f} MB, over {limit / 1e6:g} MB; the largest files: "
            + "; ".join(f"{path.relative_to(directory)} {path.stat().st_size / 1e6:.2f} MB" for path in biggest))


def kept_inputs(readme):
    """The paths (relative to doc/data) in backticks in the README's
    "Kept inputs" section."""
    if not readme.exists():
        return set()
    section = re.search(rf"^{re.escape(KEPT_INPUTS)}\s*$(.*?)(?=^## |\Z)", readme.read_text(), re.M | re.S)
    return set(re.findall(r"`([^`\s]+)`", section.group(1))) if section else set()


def run_state_files(directory):
    """Files named like a dump, restart or checkpoint that the README does
    not list as kept inputs, relative to directory."""
    allowed = kept_inputs(directory / "README.md")
    return sorted(str(path.relative_to(directory)) for path in files(directory)
                  if any(fnmatch.fnmatch(path.name, pattern) for pattern in RUN_STATE)
                  and str(path.relative_to(directory)) not in allowed)


def test_doc_data_is_under_30_mb():
    problem = size_problem(DATA)
    assert problem is None, problem


def test_doc_data_holds_no_dump_restart_or_checkpoint():
    found = run_state_files(DATA)
    assert not found, ("dumps, restarts or checkpoints in doc/data (finished runs keep their reduced records; "
                       "an unfinished run is carried in carry/<campaign>/; an input kept on purpose is "
                       f"listed under '{KEPT_INPUTS}' in doc/data/README.md): {found}")


def test_the_checks_name_the_largest_files_and_spare_the_kept_inputs(tmp_path):
    for name, size in (("a/big.npz", 900), ("a/dump.cg.xz", 500), ("b/checkpoint.10.restart.xz", 400),
                       ("b/packing_s1.restart.xz", 300), ("c.txt", 200), ("d.md", 100), ("e.md", 50)):
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_bytes(b"x" * size)
    assert size_problem(tmp_path, limit=5000) is None
    message = size_problem(tmp_path, limit=2000)
    assert message.startswith(f"{tmp_path} holds 0.0 MB, over 0.002 MB")
    assert "a/big.npz 0.00 MB" in message and "c.txt" in message and "d.md" not in message   # five
    assert run_state_files(tmp_path) == ["a/dump.cg.xz", "b/checkpoint.10.restart.xz", "b/packing_s1.restart.xz"]
    (tmp_path / "README.md").write_text("# data\n\n## Kept inputs\n\n- `b/packing_s1.restart.xz`: a packing\n\n"
                                        "## Size\n\n`a/dump.cg.xz` is not an input\n")
    assert run_state_files(tmp_path) == ["a/dump.cg.xz", "b/checkpoint.10.restart.xz"]
