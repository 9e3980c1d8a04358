"""The results tables of the pages and the README are those that
analysis.results_tables computes from doc/data: a number cannot change in a
page without the record behind it."""

import pytest

from analysis import results_tables
from analysis.results_tables import Row, markdown_table, replace_block


def test_pages_agree_with_their_records():
    stale = results_tables.stale_blocks()
    assert not stale, (f"tables differ from doc/data: {stale}; "
                       "regenerate with /usr/bin/python3 -m analysis.results_tables --write")


def test_every_scene_has_rows_with_a_window_and_a_linked_section():
    for scene, (_, page) in results_tables.SCENES.items():
        rows = results_tables.scene_rows(scene)
        assert rows, scene
        anchors = _anchors((results_tables.ROOT / page).read_text())
        for row in rows:
            assert row.window.strip(), (scene, row.quantity)
            assert row.section in anchors, f"{page} has no section #{row.section} ({row.quantity})"
            assert row.verdict != "differs" or row.cause, f"{scene}: '{row.quantity}' differs without a cause"


def test_readme_holds_each_scenes_headlines():
    readme = (results_tables.ROOT / "README.md").read_text()
    for scene in results_tables.SCENES:
        rows = results_tables.scene_rows(scene)
        assert any(row.headline for row in rows), f"{scene} has no headline row"
        for row in rows:
            if row.headline:
                assert row.ours in readme, (scene, row.quantity)


def test_a_table_replaces_only_its_own_block():
    text = ("intro\n<!-- results-table a -->\nold a\n<!-- /results-table -->\n"
            "mid\n<!-- results-table b -->\nold b\n<!-- /results-table -->\n")
    new = replace_block(text, "a", "new a\n")
    assert "new a" in new and "old a" not in new and "old b" in new and new.startswith("intro\n")
    with pytest.raises(KeyError, match="results-table c"):
        replace_block(text, "c", "x\n")


def test_a_row_needs_a_known_verdict_and_pipes_are_escaped():
    with pytest.raises(ValueError, match="verdict"):
        Row("q", "1", "2", "w", "fine", "s")
    table = markdown_table([Row("|Q|", "1 ± 0.1", "2 ± 0.2", "1-4 s", "differs", "sec", cause="why")],
                           page="doc/x.md")
    assert table.splitlines()[2] == "| \\|Q\\| | 1 ± 0.1 | 2 ± 0.2 | 1-4 s | [differs](doc/x.md#sec): why |"


def _anchors(markdown):
    """GitHub's anchors of a page's headings."""
    import re
    anchors = set()
    for line in markdown.splitlines():
        match = re.match(r"#+\s+(.*)", line)
        if match:
            slug = re.sub(r"[^\w\- ]", "", match.group(1).strip().lower()).replace(" ", "-")
            anchors.add(slug)
    return anchors
