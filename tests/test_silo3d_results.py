"""analysis.silo3d_rotating.results: the rotating silo's ratios over the same window,
from the run records in doc/data."""

import numpy as np
import pytest

from analysis.silo3d_rotating import results as sr
from analysis.results_tables import DATA_DIR


def test_a_window_rate_is_the_analysis_rate_of_that_window():
    # the campaign's analysis of the first packing at 1.28 Hz, Q over 1-4 s
    # (doc/data/silo3d_rods_fig2c/flow_rate_runs_first_packing.md)
    rate = sr.window_rate(DATA_DIR / sr.FIG2C["1st", 1.28], 1, 4)
    assert rate.q == pytest.approx(0.0850837, rel=1e-5)
    assert rate.se == pytest.approx(0.00812958, rel=1e-5)


def test_the_first_4_s_of_an_8_s_run_are_those_of_the_4_s_run():
    # the same packing and trajectory: its 4 s run at rest and its 8 s run
    long = sr.window_rate(DATA_DIR / sr.FIG2C["1st", 0.0], 1, 4)
    short = sr.window_rate(DATA_DIR / sr.ORIFICES["1st", 60], 1, 4)
    assert long.q == pytest.approx(short.q, rel=1e-9)


def test_no_rate_after_a_clog_at_rest_nor_beyond_a_runs_end():
    assert sr.window_rate(DATA_DIR / sr.FIG2C["3rd", 0.0], 1, 2) is None      # clogged at 1.37 s
    assert sr.window_rate(DATA_DIR / sr.FIG2C["1st", 0.32], 4, 8) is None     # a 4 s run
    assert sr.window_rate(DATA_DIR / sr.FIG2C["1st", 0.32], 2, 4) is not None


def test_combine_weights_and_scales_up_a_disagreement():
    agree = sr.combine([("a", 1.0, 0.1), ("b", 1.0, 0.1)])
    assert agree.value == pytest.approx(1.0) and agree.se == pytest.approx(0.1 / np.sqrt(2))
    apart = sr.combine([("a", 1.0, 0.1), ("b", 2.0, 0.1)])
    assert apart.value == pytest.approx(1.5)
    assert apart.chi2 == pytest.approx(50.0)
    assert apart.se == pytest.approx(0.1 / np.sqrt(2) * np.sqrt(50.0))


def test_the_70_over_60_mm_ratio_is_taken_over_one_window():
    ratio = sr.orifice_ratio(DATA_DIR, "2nd", 70, 60, (1, 2))
    q70 = sr.window_rate(DATA_DIR / sr.ORIFICES["2nd", 70], 1, 2)
    q60 = sr.window_rate(DATA_DIR / sr.ORIFICES["2nd", 60], 1, 2)
    assert ratio.value == pytest.approx(q70.q / q60.q)
    assert 1.8 < ratio.value < 2.2


def test_the_tables_in_doc_data_are_those_of_the_records():
    assert sr.main(["--check"]) == 0


def test_every_row_states_its_window():
    for row in sr.results_rows(DATA_DIR):
        assert row.window.strip()
        assert row.section in sr.PAGE_SECTIONS.values()
