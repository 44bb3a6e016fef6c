"""Progress reports: erosion's steps reach a callback; progress=True drives
tqdm when it is installed and prints without it."""

import sys
import types

import numpy as np
import pytest

from natura import terrain, volume


def test_erosion_reports_its_steps_and_the_result_is_unchanged():
    h = terrain.spectral((32, 32), cell_size=1.0, seed=3)
    calls = []
    a = terrain.erode_thermal(h, steps=5, progress=lambda *c: calls.append(c))
    assert np.array_equal(a, terrain.erode_thermal(h, steps=5))
    assert calls[0][1] == 0 and calls[-1][1:] == (5, 5)
    for model in (terrain.erode_hydraulic, terrain.erode_pipe, terrain.erode_stream_power,
                  terrain.erode_diffusion):
        calls.clear()
        model(h, steps=2, progress=lambda *c: calls.append(c))
        assert calls and calls[-1][1] == calls[-1][2] > 0, model.__name__
    calls.clear()
    terrain.erode_droplet(h, droplets=500, seed=1, progress=lambda *c: calls.append(c))
    assert calls and calls[-1][1] == calls[-1][2] > 0


class FakeBar:
    bars = []

    def __init__(self, total=None, desc=None, leave=True):
        self.total, self.desc, self.n, self.closed = total, desc, 0, False
        FakeBar.bars.append(self)

    def update(self, k):
        self.n += k

    def close(self):
        self.closed = True


def test_progress_true_uses_tqdm_when_installed(monkeypatch):
    fake = types.ModuleType("tqdm")
    fake.tqdm = FakeBar
    monkeypatch.setitem(sys.modules, "tqdm", fake)
    FakeBar.bars.clear()
    v = volume.cloud(cell=1.0, progress=True)
    (bar,) = FakeBar.bars
    assert bar.desc == "bake" and bar.total == bar.n == v.density.shape[0] and bar.closed


def test_progress_true_without_tqdm_prints_each_stage(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "tqdm", None)  # import tqdm raises ImportError
    volume.smoke_plume(cells=4, steps=2, progress=True)
    assert "natura: smoke done (2)" in capsys.readouterr().err
