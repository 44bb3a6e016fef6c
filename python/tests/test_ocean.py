"""natura.ocean: the fields equal the Rust API's bit for bit, the Python
defaults are the Rust defaults, bad values raise errors naming them, and the
patch keeps the properties natura-ocean promises (looping, zero mean)."""

import inspect
import math

import numpy as np
import pytest
from conftest import REFERENCE, hash_array

from natura import _native, ocean

REF = REFERENCE["ocean"]
FIELDS = ["height", "slope_x", "slope_y", "disp_x", "disp_y", "jxx", "jyy", "jxy"]


def tma_patch(**kwargs):
    """The patch of tests/reference.rs's `ocean()`."""
    args = dict(
        nx=32,
        ny=32,
        lx=80.0,
        ly=60.0,
        dispersion="finite_depth",
        depth=20.0,
        choppiness=3.0,
        spectrum=ocean.Tma(
            depth=20.0, wind_speed=14.0, fetch=20000.0, spreading_s=6.0, wind_direction=0.4
        ),
        seed=5,
        foam=True,
    )
    args.update(kwargs)
    return ocean.frames([0.0, 1.5, 4.0], **args)


def test_fields_equal_the_rust_api():
    f = tma_patch()
    assert sorted(f) == sorted(FIELDS + ["foam"])
    for name, a in f.items():
        assert a.dtype == np.float32 and a.shape == (3, 32, 32), name
        assert hash_array(a) == REF[name], name
    # Whitecaps formed, and stay within [0, 1].
    assert 0.0 < f["foam"].max() <= 1.0 and f["foam"].min() >= 0.0


def test_one_frame_is_rows_of_y():
    h = ocean.frame(
        2.0,
        nx=16,
        ny=32,
        lx=50.0,
        ly=100.0,
        spectrum=ocean.Phillips(wind_speed=9.0, small_wave_length=0.05),
    )["height"]
    assert h.shape == (32, 16)
    assert hash_array(h) == REF["phillips_height"]


def test_without_foam_there_is_no_foam_field():
    f = ocean.frames([0.0], nx=16, ny=16, lx=10.0, ly=10.0)
    assert sorted(f) == sorted(FIELDS)


def test_a_looping_patch_repeats_and_heights_have_zero_mean():
    f = ocean.frames(
        [0.0, 7.0, 2.0], nx=16, ny=16, lx=40.0, ly=40.0, loop_period=7.0, choppiness=1.0
    )
    for name in FIELDS:
        np.testing.assert_allclose(f[name][1], f[name][0], atol=1e-4, err_msg=name)
    assert not np.allclose(f["height"][2], f["height"][0])
    assert abs(float(f["height"].mean())) < 1e-4


def signature_defaults(f):
    return {
        k: p.default
        for k, p in inspect.signature(f).parameters.items()
        if p.default is not inspect.Parameter.empty
    }


@pytest.mark.parametrize(
    "name, f",
    [
        ("ocean", ocean.frames),
        ("foam", ocean.FoamParams),
        ("phillips", ocean.Phillips),
        ("pierson_moskowitz", ocean.PiersonMoskowitz),
        ("jonswap", ocean.Jonswap),
        ("tma", ocean.Tma),
    ],
)
def test_python_defaults_are_the_rust_defaults(name, f):
    ours = signature_defaults(f)
    for k, v in _native.ocean_defaults(name).items():
        assert ours[k] == v, (name, k)


def test_every_spectrum_has_a_class():
    classes = {ocean.Phillips, ocean.PiersonMoskowitz, ocean.Jonswap, ocean.Tma}
    assert sorted(c.kind for c in classes) == sorted(_native.OCEAN_SPECTRA)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(nx=100), "nx"),
        (dict(lx=0.0), "lx"),
        (dict(choppiness=-1.0), "choppiness"),
        (dict(k_min=2.0, k_max=1.0), "k_max"),
        (dict(loop_period=-3.0), "loop_period"),
        (dict(amplitudes="uniform"), "amplitudes"),
        (dict(dispersion="shallow"), "dispersion"),
        (dict(dispersion="finite_depth"), "depth"),
        (dict(depth=5.0), "depth"),
        (dict(dispersion="capillary"), "capillary_length"),
        (dict(spectrum=ocean.Phillips(wind_speed=-1.0)), "wind_speed"),
        (dict(spectrum=ocean.Jonswap(fetch=float("nan"))), "fetch"),
        (dict(spectrum=ocean.Jonswap(spreading="wide")), "spreading"),
        (dict(spectrum=ocean.Jonswap(spreading="hasselmann", spreading_s=6.0)), "spreading_s"),
        (dict(spectrum={"kind": "swell"}), "kind"),
        (dict(foam=ocean.FoamParams(decay_time=0.0)), "decay_time"),
    ],
)
def test_bad_values_raise_value_error_naming_them(kwargs, name):
    args = dict(nx=16, ny=16, lx=10.0, ly=10.0)
    args.update(kwargs)
    with pytest.raises(ValueError, match=name):
        ocean.frames([0.0], **args)


def test_bad_times_and_unknown_keys():
    with pytest.raises(ValueError, match="times"):
        ocean.frames([1.0, 0.5], nx=16, ny=16, foam=True)
    with pytest.raises(ValueError, match="times"):
        ocean.frames([math.nan], nx=16, ny=16)
    with pytest.raises(ValueError, match="times"):
        ocean.frames([], nx=16, ny=16)
    with pytest.raises(TypeError, match="unknown parameter 'swell'"):
        ocean.frames([0.0], nx=16, ny=16, spectrum={"kind": "phillips", "swell": 1.0})
    # Without foam, times may run in any order.
    f = ocean.frames([1.0, 0.5], nx=16, ny=16, lx=10.0, ly=10.0)
    g = ocean.frames([0.5], nx=16, ny=16, lx=10.0, ly=10.0)
    assert np.array_equal(f["height"][1], g["height"][0])
