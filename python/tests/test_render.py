"""natura.render: a scene (dict or TOML) to a float image equal to the Rust
render_scene's, bad keys named, progress reported."""

import numpy as np
import pytest

from natura import render
from conftest import REFERENCE, hash_array

REF = REFERENCE["render"]


def test_the_quick_scene_equals_the_rust_api_bit_for_bit():
    img, ev = render.render_with_exposure(render.QUICK, width=48, height=27)
    assert img.dtype == np.float32 and img.shape == (27, 48, 3)
    assert hash_array(img) == REF["quick_48x27"]
    assert np.float32(ev).view(np.uint32) == REF["exposure_bits"]
    # The top-left pixel is sky: bluer than it is red.
    assert img[0, 0, 2] > img[0, 0, 0]


def test_a_dict_and_its_toml_text_give_the_same_image():
    text = render.scene_toml(render.QUICK)
    assert "size = 64" in text and "[sun]" in text
    a = render.render(render.QUICK, width=24, height=14)
    b = render.render(text, width=24, height=14)
    assert np.array_equal(a, b)
    # The overrides act: another seed gives another terrain.
    c = render.render(render.QUICK, width=24, height=14, seed=99)
    assert not np.array_equal(a, c)


def test_bad_keys_and_values_raise_value_error_naming_them():
    with pytest.raises(ValueError, match=r"sun\.elevation"):
        render.render({"sun": {"elevation": 12.0}})
    with pytest.raises(ValueError, match="colour"):
        render.render({**render.QUICK, "colour": 1})
    with pytest.raises(ValueError, match="elevation_deg"):
        render.scene_toml({"sun": {"elevation_deg": "high"}})
    with pytest.raises(ValueError, match="width"):
        render.render(render.QUICK, width=0)
    with pytest.raises(ValueError, match="scene"):
        render.render("[terrain\nsize = 3")
    with pytest.raises(TypeError, match="scene"):
        render.render(42)
    with pytest.raises(TypeError, match="terrain.size"):
        render.scene_toml({"terrain": {"size": None}})


def test_progress_hears_every_stage_and_its_tiles():
    calls = []
    render.render(render.QUICK, width=24, height=14, progress=lambda *a: calls.append(a))
    stages = [c[0] for c in calls]
    for s in ("synthesis", "stream power", "thermal", "tracing"):
        assert s in stages
    tracing = [c for c in calls if c[0] == "tracing"]
    total = tracing[0][2]
    assert total > 0 and tracing[-1][1] == total
    done = [c[1] for c in tracing]
    assert done == sorted(done), "done never goes backwards within a stage"


def test_an_exception_in_the_callback_is_raised_after_the_call():
    def bad(stage, done, total):
        raise KeyError("stop")

    with pytest.raises(KeyError, match="stop"):
        render.render(render.QUICK, width=16, height=9, progress=bad)
    with pytest.raises(TypeError, match="progress"):
        render.render(render.QUICK, width=16, height=9, progress=3)


def test_quick_previews_any_scene_as_the_rust_examples_do():
    import tomllib

    full = tomllib.loads(render.scene_toml())
    q = tomllib.loads(render.scene_toml(quick=True))
    assert q["terrain"]["size"] == 256
    extent = lambda s: s["terrain"]["size"] * s["terrain"]["cell_size_m"]
    assert extent(q) == pytest.approx(extent(full), rel=1e-6)
    assert q["erosion"]["hydraulic_steps"] == min(20, full["erosion"]["hydraulic_steps"])
    assert q["clouds"]["voxel_m"] == pytest.approx(4 * full["clouds"]["voxel_m"])
    assert q["camera"] == full["camera"] and q["render"] == full["render"]
    # A scene of 1024 samples of 12.5 m keeps its 12.8 km on 256 of 50 m.
    small = {
        "terrain": {"size": 1024, "cell_size_m": 12.5},
        "clouds": {"enabled": False},
        "vegetation": {"enabled": False},
    }
    text = render.scene_toml(small, quick=True)
    assert tomllib.loads(text)["terrain"]["cell_size_m"] == 50.0
    # Rendering with quick renders that preview, bit for bit.
    a = render.render(small, quick=True, width=24, height=14)
    b = render.render(text, width=24, height=14)
    assert np.array_equal(a, b)
