"""The boundary between Python and Rust: the GIL is released during long
calls and a Rust panic arrives as RuntimeError."""

import threading
import time

import numpy as np
import pytest

from natura import _native, terrain


def test_a_rust_panic_becomes_runtime_error():
    with pytest.raises(RuntimeError, match="panic.*boundary check"):
        _native._panic_for_test("boundary check")
    # The interpreter is intact afterwards.
    assert terrain.spectral((8, 8), seed=1).shape == (8, 8)


def test_the_gil_is_released_during_a_long_erosion():
    h = terrain.spectral((256, 256), cell_size=10.0, seed=1)
    ticks = []
    done = threading.Event()

    def erode():
        try:
            terrain.erode_hydraulic(h, cell_size=10.0, steps=400)
        finally:
            done.set()

    worker = threading.Thread(target=erode)
    worker.start()
    # This thread runs Python code while the erosion runs: it can only if
    # the erosion released the GIL.
    while not done.is_set():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    worker.join()
    assert len(ticks) >= 20, f"only {len(ticks)} ticks of the main thread during the erosion"


def test_the_gil_is_released_during_a_render_with_progress():
    from natura import render

    ticks = []
    heard = []
    done = threading.Event()

    def work():
        try:
            # The callback takes the GIL from the renderer's worker threads
            # and gives it back.
            render.render(render.QUICK, spp=4, progress=lambda *a: heard.append(a))
        finally:
            done.set()

    worker = threading.Thread(target=work)
    worker.start()
    while not done.is_set():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    worker.join()
    assert heard and len(ticks) >= 20, f"only {len(ticks)} ticks of the main thread"
