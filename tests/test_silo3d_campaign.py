"""analysis.campaign.silo3d_status: how far each run of a campaign has got and
what it cost, from hand-made records, by hand."""

from analysis.campaign import silo3d_status

RUN_TXT = "# run\nd 0.006\nf {f}\nD 0.06\nseed {seed}\ndt 0.001\ndischarge_time 4.0\ndischarge_time {length}\n"


def write_run(directory, f, seed, length, rows, loops, finished=False):
    """run.txt (the last discharge_time counts), discharge.txt with rows
    up to time `rows`, screen.txt with (seconds, procs, steps) loop lines."""
    directory.mkdir(parents=True)
    (directory / "run.txt").write_text(RUN_TXT.format(f=f, seed=seed, length=length))
    (directory / "discharge.txt").write_text("# step t n_out mass_out\n" + "".join(
        f"{round(t / 0.001)} {t} {k} {k * 1e-3}\n" for k, t in enumerate([0.01 * j for j in range(1, round(rows / 0.01) + 1)])))
    (directory / "screen.txt").write_text("LIGGGHTS\n" + "".join(
        f"Loop time of {seconds} on {procs} procs for {steps} steps with 10000 atoms, finish time x\n"
        for seconds, procs, steps in loops))
    if finished:
        (directory / "finished").touch()


def test_progress_cost_and_what_is_left_by_hand(tmp_path, capsys):
    # a run at 2 s of 8: loops of 1800 s and 1800 s on one process for
    # 1000 steps each (2 simulated s at dt 1 ms): 1 h, 0.5 h per simulated
    # s, 6 s left = 3 h. A finished run on two processes: 900 s x 2 for
    # 1000 steps = 0.5 h, 0.5 h per s, none left
    campaign = tmp_path / "campaign"
    write_run(campaign / "D0.06_f0.16_s1", 0.16, 1, 8.0, 2.0, [(1800, 1, 1000), (1800, 1, 1000)])
    write_run(campaign / "D0.06_f0_s1", 0.0, 1, 1.0, 1.0, [(900, 2, 1000)], finished=True)
    (campaign / "packing_s1").mkdir()
    rows = {r["run"]: r for r in map(silo3d_status.run_status, silo3d_status.run_dirs([campaign]))}
    assert sorted(rows) == ["D0.06_f0.16_s1", "D0.06_f0_s1"]
    turning, rest = rows["D0.06_f0.16_s1"], rows["D0.06_f0_s1"]
    assert turning["t"] == 2.0 and turning["length"] == 8.0 and not turning["finished"]
    assert turning["cpu_hours"] == 1.0 and turning["per_second"] == 0.5 and turning["left"] == 3.0
    assert rest["finished"] and rest["cpu_hours"] == 0.5 and rest["per_second"] == 0.5 and rest["left"] == 0.0
    assert silo3d_status.main([str(campaign)]) == 0
    out = capsys.readouterr().out
    assert "| D0.06_f0.16_s1 | 0.16 | 0.06 | 1 | 2.00 / 8 | at 2.00 s | 1.00 | 0.50 | 3.00 |" in out
    assert "1 of 2 runs finished; 1.5 loop hours spent, 3.0 left" in out
    # a run the deck stopped at a clog (run.txt's `clogged`): finished at
    # 1.5 s of its 8, nothing left
    write_run(campaign / "D0.06_f0_s2", 0.0, 2, 8.0, 1.5, [(900, 1, 1000)], finished=True)
    with open(campaign / "D0.06_f0_s2" / "run.txt", "a") as run_txt:
        run_txt.write("clogged 1.5\nfinished 1.5\n")
    clogged = silo3d_status.run_status(campaign / "D0.06_f0_s2")
    assert clogged["clogged"] == 1.5 and clogged["left"] == 0.0 and rest["clogged"] is None
    assert silo3d_status.main([str(campaign)]) == 0
    assert "| D0.06_f0_s2 | 0 | 0.06 | 2 | 1.50 / 8 | finished, clogged (stopped at 1.50 s) |" in capsys.readouterr().out
    # a run directory given itself; nothing to show is an error
    assert silo3d_status.run_dirs([campaign / "D0.06_f0_s1"]) == [campaign / "D0.06_f0_s1"]
    assert silo3d_status.main([str(tmp_path / "empty")]) == 2
