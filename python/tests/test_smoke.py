"""natura.volume.SmokeSolver: natura-fluid's smoke solver set up from Python
steps to the Rust preset's fields bit for bit, its smoke rises and flows
round what is in its way, and bad input is refused naming it."""

import threading

import numpy as np
import pytest

from natura import volume


def plume_by_hand(cells: int, cell: float) -> volume.SmokeSolver:
    """The Rust ``Plume`` preset (width 1, epsilon 4) built through the
    general set-up."""
    s = volume.SmokeSolver(
        (cells, cells, 2 * cells), cell, epsilon=4.0,
        advection={"interpolation": {"monotone_cubic": "fritsch_carlson"}},
    )
    s.add_obstacle(volume.sphere((0.45, 0.5, 0.85), 0.15))
    s.add_source(volume.sphere((0.5, 0.5, 0.15), 0.08), density=1.0, temperature=330.0,
                 velocity=(0.0, 0.0, 0.3))
    return s


def test_the_plume_set_up_by_hand_steps_to_the_preset_bit_for_bit():
    preset = volume.smoke_plume(cells=16, steps=4)
    s = plume_by_hand(16, preset.cell)
    calls = []
    report = s.step(preset.dt, steps=4, progress=lambda *a: calls.append(a))
    assert calls == [("smoke", k, 4) for k in range(5)] + [("smoke", 4, 4)]
    np.testing.assert_array_equal(s.density, preset.density)
    np.testing.assert_array_equal(s.temperature, preset.temperature)
    assert s.time == pytest.approx(4 * preset.dt)
    assert report["converged"] and report["max_speed"] > 0.0
    assert report["max_speed"] * preset.dt / preset.cell < 1.0
    assert s.solid.dtype == np.bool_ and s.solid.shape == (32, 16, 16) and s.solid.any()
    u, v, w = s.velocity
    assert u.shape == (32, 16, 17) and v.shape == (32, 17, 16) and w.shape == (33, 16, 16)
    # A different set-up gives a different field: the comparison can fail.
    other = plume_by_hand(16, preset.cell)
    other.add_source(volume.cuboid((0.1, 0.1, 0.05), (0.2, 0.2, 0.1)), density=1.0,
                     temperature=300.0)
    other.step(preset.dt, steps=4)
    assert not np.array_equal(other.density, preset.density)


def test_warm_smoke_rises_and_a_cold_heavy_one_sinks():
    def height(temperature: float, alpha: float) -> float:
        s = volume.SmokeSolver((12, 12, 24), 0.05, alpha=alpha)
        d = np.zeros((24, 12, 12), np.float32)
        d[8:12, 4:8, 4:8] = 1.0
        t = np.full((24, 12, 12), 293.15, np.float32)
        t[8:12, 4:8, 4:8] = temperature
        s.set_density(d)
        s.set_temperature(t)
        z = np.arange(24, dtype=np.float64)[:, None, None]
        before = float((s.density * z).sum() / s.density.sum())
        s.step(0.02, steps=15)
        return float((s.density * z).sum() / s.density.sum()) - before

    assert height(340.0, 0.0) > 0.5
    assert height(293.15, 5.0) < -0.5


def test_a_grid_one_cell_deep_is_a_2d_simulation_in_the_x_z_plane():
    s = volume.SmokeSolver((16, 1, 32), 0.05)
    s.add_source(volume.sphere((0.4, 0.025, 0.2), 0.1), density=1.0, temperature=340.0)
    s.step(0.02, steps=40)
    d = s.density
    assert d.shape == (32, 1, 16)
    # The warm smoke has risen from its source at 0.2 m to above 0.45 m.
    assert np.nonzero(d.max(axis=(1, 2)) > 0.01)[0].max() * s.cell > 0.45
    assert [a.shape for a in s.velocity] == [(32, 1, 17), (32, 2, 16), (33, 1, 16)]
    assert np.all(s.velocity[1] == 0.0)


def test_a_force_pushes_the_smoke_along_it_and_only_while_given():
    def centre_x(force) -> float:
        s = volume.SmokeSolver((24, 8, 8), 0.05)
        d = np.zeros((8, 8, 24), np.float32)
        d[2:6, 2:6, 10:14] = 1.0
        s.set_density(d)
        s.step(0.02, steps=10, force=force)
        x = np.arange(24, dtype=np.float64)[None, None, :]
        return float((s.density * x).sum() / s.density.sum())

    zero = np.zeros((8, 8, 24), np.float32)
    wind = (np.full((8, 8, 24), 2.0, np.float32), zero, zero)
    still = centre_x(None)
    assert still == pytest.approx(11.5, abs=0.05)
    assert centre_x(wind) > still + 0.5
    assert centre_x((-wind[0], zero, zero)) < still - 0.5
    assert centre_x((zero, zero, zero)) == still
    s = volume.SmokeSolver((4, 4, 4), 0.1)
    with pytest.raises(ValueError, match="three"):
        s.step(0.01, force=[zero])
    with pytest.raises(ValueError, match=r"force\[1\]"):
        s.step(0.01, force=[np.zeros((4, 4, 4), np.float32), np.full((4, 4, 4), np.inf, np.float32),
                            np.zeros((4, 4, 4), np.float32)])


def test_a_moving_obstacle_and_a_hot_one_act_on_the_air():
    s = volume.SmokeSolver((16, 8, 8), 0.1)
    s.add_obstacle(volume.oriented_box((0.8, 0.4, 0.4), (0.1, 0.2, 0.2)),
                   velocity=(0.5, 0.0, 0.0), temperature=400.0)
    s.step(0.02, steps=3)
    # The hot block warms the air round it and pushes it along +x.
    assert s.temperature.max() == pytest.approx(400.0)
    u = s.velocity[0]
    assert u.max() > 0.1


def test_an_ellipsoid_obstacle_pushes_the_air():
    s = volume.SmokeSolver((16, 8, 8), 0.1)
    s.add_obstacle(volume.ellipsoid((0.6, 0.4, 0.4), (0.3, 0.15, 0.15)), velocity=(0.5, 0.0, 0.0))
    s.step(0.02, steps=3)
    assert s.velocity[0].max() > 0.1
    with pytest.raises(ValueError, match="shape"):
        s.add_obstacle(volume.ellipsoid((0.6, 0.4, 0.4), (0.3, 0.0, 0.15)))


def test_params_are_the_rust_defaults_and_the_solver_renders_and_writes(tmp_path):
    s = volume.SmokeSolver((8, 8, 16), 0.0625)
    p = s.params
    assert p["alpha"] == pytest.approx(0.05) and p["ambient_temperature"] == pytest.approx(293.15)
    assert s.dims == (8, 8, 16) and s.cell == 0.0625 and s.time == 0.0
    s.add_source(volume.sphere((0.25, 0.25, 0.2), 0.1), density=1.0, temperature=320.0)
    s.step(0.05, steps=3)
    v = s.volume()
    img = volume.render(v, eye=(0.25, -1.5, 0.5), target=(0.25, 0.25, 0.5), width=16, height=16)
    assert img.shape == (16, 16, 3) and np.isfinite(img).all()
    volume.write_vdb(tmp_path / "smoke.vdb", v)
    back = volume.read_vdb(tmp_path / "smoke.vdb")["density"]
    assert back.density.max() == pytest.approx(v.density.max())


def test_bad_input_is_refused_naming_it():
    with pytest.raises(ValueError, match="dims"):
        volume.SmokeSolver((0, 4, 4), 0.1)
    with pytest.raises(ValueError, match="cell size"):
        volume.SmokeSolver((4, 4, 4), float("nan"))
    with pytest.raises(ValueError, match="alpah"):
        volume.SmokeSolver((4, 4, 4), 0.1, alpah=1.0)
    with pytest.raises(ValueError, match="epsilon"):
        volume.SmokeSolver((4, 4, 4), 0.1, epsilon=-1.0)
    s = volume.SmokeSolver((8, 8, 8), 0.1)
    with pytest.raises(ValueError, match="ball"):
        s.add_source({"kind": "ball", "centre": [0.4, 0.4, 0.4], "radius": 0.1},
                     density=1.0, temperature=300.0)
    with pytest.raises(ValueError, match="outside"):
        s.add_source(volume.sphere((5.0, 0.4, 0.4), 0.1), density=1.0, temperature=300.0)
    with pytest.raises(ValueError, match="temperature"):
        s.add_source(volume.sphere((0.4, 0.4, 0.4), 0.1), density=1.0, temperature=-3.0)
    with pytest.raises(ValueError, match="shape"):
        s.add_obstacle(volume.oriented_box((0.4, 0.4, 0.4), (0.1, 0.1, 0.1), (0.0, 0.0, 0.0, 2.0)))
    with pytest.raises(ValueError, match="shape"):
        s.add_obstacle(volume.sphere((0.4, 0.4, 0.4), float("nan")))
    with pytest.raises(ValueError, match="density"):
        s.set_density(np.zeros((8, 8, 7), np.float32))
    with pytest.raises(ValueError, match="density"):
        s.set_density(np.full((8, 8, 8), np.nan, np.float32))
    with pytest.raises(ValueError, match="temperature"):
        s.set_temperature(np.zeros((8, 8, 8), np.float32))
    with pytest.raises(TypeError, match="density"):
        s.set_density(np.zeros((8, 8, 8)))
    with pytest.raises(ValueError, match="dt"):
        s.step(float("nan"))
    with pytest.raises(ValueError, match="steps"):
        s.step(0.01, steps=0)
    # Nothing refused above changed the solver.
    assert s.time == 0.0 and s.density.max() == 0.0


def test_stepping_releases_the_gil():
    s = plume_by_hand(24, 1.0 / 24.0)
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(1)

    t = threading.Thread(target=count)
    t.start()
    try:
        s.step(0.03, steps=6)
    finally:
        done.set()
        t.join()
    assert len(ticks) > 100
