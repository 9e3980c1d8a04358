"""analysis.silo2d.driver, the resumable clogging-silo campaign, on the
deck's small silo (-var quick 1, 230 grains) at dt = 2e-5 s.

A campaign is a chain of segments, each started from the restart file of
the one before. The driver is killed in the middle of a segment, after
that segment has written clog records past its restart file (as the end
of a session would cut it), then called again: it runs the cut segment
again from the same restart file, fix clog removes the rows the cut
segment had written, and the records come out as those of a campaign that
was never cut, byte for byte."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from analysis.silo2d import driver as silo2d_driver
from analysis.common.tables import read_table

ROOT = Path(__file__).resolve().parent.parent
RECORDS = ("clogs.txt", "arches.txt", "feet.txt", "contacts.txt", "reinject.txt")
# four arches take 2-3 segments of 2 s in the small silo at mu = 0.4
CAMPAIGN = ["--mu", "0.4", "--arches", "4", "--quick", "--dt", "2e-5", "--segment-time", "2"]


def driver_command(out, options=CAMPAIGN):
    return [sys.executable, "-m", "analysis.silo2d.driver", "--campaign", str(out)] + list(options)


def driver_environment(binary):
    return dict(os.environ, SILOKIT_LIGGGHTS=str(binary), PYTHONPATH=str(ROOT))


def run_driver(out, binary, options=CAMPAIGN, environment=None):
    """The driver's CLI; `environment` (default: LIGGGHTS `binary`'s) for another host."""
    return subprocess.run(driver_command(out, options), cwd=ROOT,
                          env=environment or driver_environment(binary),
                          capture_output=True, text=True, timeout=600)


def cut_in_a_segment(out, environment, options=CAMPAIGN):
    """Starts the campaign and kills it (with its engine) as soon as a
    segment after the first (one that starts from a restart file) has
    recorded a clog past the last complete segment. Returns (complete
    segments, clog rows at the cut)."""
    run = out / "mu0.4"
    process = subprocess.Popen(driver_command(out, options), cwd=ROOT, env=environment,
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                               start_new_session=True)
    try:
        deadline = time.time() + 600
        while time.time() < deadline:
            done = silo2d_driver.completed_segments(run) if (run / "segments.txt").exists() else []
            recorded = int(done[-1]["clogs"]) if done else 0
            clogs, _ = silo2d_driver.count_records(run)
            if done and clogs > recorded:
                os.killpg(process.pid, signal.SIGKILL)
                process.wait()
                return len(done), clogs
            if process.poll() is not None:
                pytest.fail("the campaign ended before a segment could be cut after a clog")
            time.sleep(0.02)
        pytest.fail("no clog recorded within 600 s")
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()


def assert_cut_campaign_resumes_as_uncut(tmp_path, environment, options=CAMPAIGN):
    """Runs the campaign uncut, then cut in a segment and resumed (both
    through the CLI with `environment`), and compares their records."""
    uncut = run_driver(tmp_path / "uncut", None, options, environment)
    assert uncut.returncode == 0, uncut.stdout + uncut.stderr
    assert "silo2d_driver: mu 0.4: 4 arches" in uncut.stdout or \
           "silo2d_driver: mu 0.4: 5 arches" in uncut.stdout, uncut.stdout

    complete, clogs_at_cut = cut_in_a_segment(tmp_path / "cut", environment, options)
    cut_run = tmp_path / "cut" / "mu0.4"
    assert not (cut_run / f"state{complete + 1}.restart").exists()
    resumed = run_driver(tmp_path / "cut", None, options, environment)
    assert resumed.returncode == 0, resumed.stdout + resumed.stderr

    # the cut segment ran again and fix clog removed what it had written
    log = (cut_run / "logs" / f"segment{complete + 1}.txt").read_text()
    assert "fix clog: removed" in log and "from 'clogs.txt'" in log
    uncut_run = tmp_path / "uncut" / "mu0.4"
    for name in RECORDS:
        assert (cut_run / name).read_text() == (uncut_run / name).read_text(), name
    clogs = read_table(cut_run / "clogs.txt")
    assert len(clogs["clog"]) >= clogs_at_cut
    assert list(clogs["clog"]) == list(range(1, len(clogs["clog"]) + 1))

    # the same segments, apart from their times
    columns = ("segment", "last_clog_time", "clogs", "arches")
    cut_segments = silo2d_driver.completed_segments(cut_run)
    uncut_segments = silo2d_driver.completed_segments(uncut_run)
    assert [[row[c] for c in columns] for row in cut_segments] == \
           [[row[c] for c in columns] for row in uncut_segments]
    assert len(uncut_segments) >= 2     # the chain was exercised, not one segment
    # only the last two restart files are kept
    assert sorted(p.name for p in uncut_run.glob("state*.restart")) == \
           [f"state{k}.restart" for k in (len(uncut_segments) - 1, len(uncut_segments))]


@pytest.mark.engine
def test_a_cut_campaign_resumed_records_what_an_uncut_one_does(liggghts_binary, tmp_path):
    assert_cut_campaign_resumes_as_uncut(tmp_path, driver_environment(liggghts_binary))


@pytest.mark.engine
def test_a_campaign_refuses_other_parameters(liggghts_binary, tmp_path):
    """parameters.txt is written before the first segment; calling again
    with another time step would mix two set-ups in one record."""
    first = run_driver(tmp_path, liggghts_binary, CAMPAIGN + ["--max-segments", "0"])
    assert first.returncode == 0, first.stderr
    assert "dt 2e-05" in (tmp_path / "mu0.4" / "parameters.txt").read_text().splitlines()
    options = [o if o != "2e-5" else "1e-5" for o in CAMPAIGN]
    second = run_driver(tmp_path, liggghts_binary, options + ["--max-segments", "0"])
    assert second.returncode != 0
    assert "was started with other parameters" in second.stderr
    assert "dt 1e-05" in second.stderr


@pytest.mark.parametrize("option, message", [
    (["--arches", "0"], "--arches must be >= 1"),
    (["--segment-time", "0"], "--segment-time must be > 0"),
    (["--dt", "-1"], "--dt must be > 0"),
    (["--var", "segment=3"], "--var segment: set by the driver itself"),
    (["--var", "segment"], "--var segment: expected NAME=VALUE"),
])
def test_bad_options_are_refused(tmp_path, option, message):
    with pytest.raises(SystemExit):
        silo2d_driver.parse(["--campaign", str(tmp_path), "--mu", "0.4", "--arches", "3"] + option)
