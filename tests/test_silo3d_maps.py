"""analysis.silo3d_rotating.maps: the mean of a run's map windows, weighted by
their frames, by hand; runs side by side; what a run lacks is refused."""

import numpy as np
import pytest

from analysis.silo3d_rotating import maps as silo3d_maps


def write_fields(path, phi_per_window, frames, orientation=True, cells=(3, 4)):
    """A fields.npz as analysis.silo3d_rotating.analyse writes it: grid, windows,
    frames and per window the maps (phi constant per window; one cell NaN
    in the first window, as a cell without grains)."""
    nr, nz = cells
    stored = {"r": np.linspace(0.005, 0.025, nr), "z": np.linspace(0.005, 0.035, nz),
              "r_edges": np.linspace(0, 0.03, nr + 1), "z_edges": np.linspace(0, 0.04, nz + 1),
              "windows": np.array([[k, k + 1.0] for k in range(len(frames))]), "frames": np.array(frames)}
    for w, phi in enumerate(phi_per_window):
        values = np.full((nr, nz), phi)
        if w == 0:
            values[0, 0] = np.nan
        stored[f"packing_fraction_{w}"] = values
        stored[f"velocity_{w}"] = np.zeros((nr, nz, 3)) + [0.0, 0.1, -0.2 * (w + 1)]
        stored[f"kinetic_pressure_{w}"] = np.ones((nr, nz))
        if orientation:
            o = np.zeros((nr, nz, 3, 3))
            o[..., 2, 2] = 0.5 + 0.1 * w
            stored[f"orientation_{w}"] = o
            stored[f"nematic_order_{w}"] = np.full((nr, nz), 0.6)
    np.savez(path, **stored)
    return path


def test_the_mean_of_the_windows_is_weighted_by_their_frames_by_hand(tmp_path):
    # windows of 1 and 3 frames: phi 0.2 and 0.6 -> (0.2 + 3 * 0.6)/4 = 0.5;
    # the cell empty in the first window takes the second's 0.6; O_zz
    # (0.5 + 3 * 0.6)/4 = 0.575; v_z -(0.2 + 3 * 0.4)/4 = -0.35
    fields = silo3d_maps.mean_fields(write_fields(tmp_path / "a.npz", [0.2, 0.6], [1, 3]))
    phi = fields["maps"]["packing_fraction"]
    assert phi[0, 0] == pytest.approx(0.6) and np.delete(phi.ravel(), 0) == pytest.approx(0.5)
    assert fields["maps"]["orientation"][..., 2, 2] == pytest.approx(0.575)
    assert fields["maps"]["velocity"][..., 2] == pytest.approx(-0.35)
    # a window without frames does not count
    empty = silo3d_maps.mean_fields(write_fields(tmp_path / "b.npz", [0.2, 0.6], [2, 0]))
    assert np.delete(empty["maps"]["packing_fraction"].ravel(), 0) == pytest.approx(0.2)


def test_runs_side_by_side_and_what_they_lack_is_refused(tmp_path, capsys):
    rods = write_fields(tmp_path / "rods.npz", [0.3, 0.4], [2, 2])
    turning = write_fields(tmp_path / "turning.npz", [0.5, 0.5], [1, 1])
    out = tmp_path / "maps.png"
    assert silo3d_maps.main([f"{rods}:f = 0", f"{turning}:f = 0.16 Hz", "--figure", str(out),
                             "--fields", "phi", "speed", "Ozz", "S", "--z-max-m", "0.03"]) == 0
    assert out.stat().st_size > 0
    assert "f = 0: mean of the windows 0-1 s, 1-2 s" in capsys.readouterr().out
    spheres = write_fields(tmp_path / "spheres.npz", [0.3], [1], orientation=False)
    assert silo3d_maps.main([str(rods), str(spheres), "--figure", str(out), "--fields", "phi", "Ozz"]) == 2
    assert "has no map for Ozz" in capsys.readouterr().err
    other_grid = write_fields(tmp_path / "other.npz", [0.3], [1], cells=(4, 4))
    assert silo3d_maps.main([str(rods), str(other_grid), "--figure", str(out)]) == 2
    assert "the runs' grids differ" in capsys.readouterr().err
    assert silo3d_maps.main([str(tmp_path / "missing.npz"), "--figure", str(out)]) == 2
