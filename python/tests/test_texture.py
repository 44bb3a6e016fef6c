"""natura.texture and natura.atmos: textures and the sky equal to the Rust
API's."""

import math

import numpy as np
import pytest

from natura import atmos, texture
from conftest import REFERENCE, hash_array, points3

REF = REFERENCE["texture"]


@pytest.mark.parametrize("name", ["terran", "puffy_clouds"])
def test_samples_equal_the_rust_api_bit_for_bit(name):
    s = texture.sample(name, points3(), footprint=1e-3)
    assert s.colour.dtype == np.float64 and s.colour.shape == (37, 3)
    assert hash_array(s.colour) == REF[f"{name}_colour"]
    assert hash_array(s.opacity) == REF[f"{name}_opacity"]
    assert hash_array(s.height) == REF[f"{name}_height"]
    # float32 points are the same points.
    s32 = texture.sample(name, points3().astype(np.float32).astype(np.float64))
    s32b = texture.sample(name, points3().astype(np.float32))
    assert np.array_equal(s32.colour, s32b.colour)


@pytest.mark.parametrize("name", texture.NAMES)
def test_every_texture_samples_valid_values_and_has_defaults(name):
    d = texture.defaults(name)
    assert isinstance(d, dict) and d
    s = texture.sample(name, points3() * 0.1, **d)
    assert np.all(np.isfinite(s.colour)) and s.colour.min() >= 0.0 and s.colour.max() <= 1.0
    assert np.all((s.opacity >= 0.0) & (s.opacity <= 1.0))


def test_equirect_is_the_texture_on_the_sphere():
    img = texture.equirect("terran", 16, 8)
    assert img.shape == (8, 16, 3) and img.dtype == np.float32
    lat = math.pi / 2 - 2.5 * math.pi / 8
    lon = -math.pi + 5.5 * 2 * math.pi / 16
    p = np.array([[math.cos(lat) * math.cos(lon), math.cos(lat) * math.sin(lon), math.sin(lat)]])
    s = texture.sample("terran", p, footprint=2 * math.pi / 16)
    np.testing.assert_allclose(img[2, 5], s.colour[0].astype(np.float32), rtol=1e-6, atol=1e-7)


def test_git_texture_from_a_palette_and_the_git_filter():
    palette = np.array([[0.78, 0.52, 0.36], [0.66, 0.42, 0.30], [0.72, 0.50, 0.40], [0.60, 0.36, 0.24]])
    e = texture.colour_ellipsoid(palette)
    np.testing.assert_allclose(e["mean"], palette.mean(axis=0), rtol=1e-12)
    assert len(e["axes"]) == 3 and e["sigma"][0] >= e["sigma"][1] >= e["sigma"][2] >= 0.0
    s = texture.sample("git", points3() * 3.0, ellipsoid=e)
    assert np.all((s.colour >= 0.0) & (s.colour <= 1.0))
    # The filter: an image four times larger, finite, deterministic; a flat
    # picture stays flat.
    img = np.zeros((12, 16, 3), dtype=np.float32)
    img[..., 0] = np.linspace(0.0, 1.0, 16, dtype=np.float32)
    img[..., 1] = 0.4
    out = texture.git_filter(img, seed=3)
    assert out.shape == (48, 64, 3) and out.dtype == np.float32 and np.all(np.isfinite(out))
    assert np.array_equal(out, texture.git_filter(img, seed=3))
    flat = texture.git_filter(np.full((6, 5, 3), 0.2, dtype=np.float32), expand=2)
    assert flat.shape == (12, 10, 3) and np.allclose(flat, 0.2, atol=1e-4)
    assert texture.git_filter_defaults()["expand"] == 4
    with pytest.raises(ValueError, match="expand"):
        texture.git_filter(img, expand=0)
    with pytest.raises(ValueError, match="image"):
        texture.git_filter(np.zeros((4, 4, 2), dtype=np.float32))
    with pytest.raises(TypeError, match="image"):
        texture.git_filter(np.zeros((4, 4, 3), dtype=np.float64))
    bad = img.copy()
    bad[2, 3, 1] = np.nan
    with pytest.raises(ValueError, match="image"):
        texture.git_filter(bad)
    with pytest.raises(ValueError, match="colours"):
        texture.colour_ellipsoid(palette[:1])


def test_bad_names_values_and_arrays_are_named():
    with pytest.raises(ValueError, match="name"):
        texture.sample("marble", np.zeros((1, 3)))
    with pytest.raises(ValueError, match="octavs"):
        texture.sample("terran", np.zeros((1, 3)), octavs=3)
    with pytest.raises(ValueError, match="footprint"):
        texture.sample("terran", np.zeros((1, 3)), footprint=-1.0)
    with pytest.raises(ValueError, match=r"points.*\(n, 3\)"):
        texture.sample("terran", np.zeros((4, 2)))
    with pytest.raises(TypeError, match="points"):
        texture.sample("terran", np.zeros((4, 3), dtype=np.int32))


def sky_directions():
    d = []
    for k in range(40):
        e, a = k * 0.07 - 0.2, k * 0.37
        d.append([math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)])
    return np.array(d, dtype=np.float64)


def test_sky_equals_the_rust_api_bit_for_bit():
    r = atmos.sky(sky_directions(), sun_elevation_deg=12.0, sun_azimuth_deg=40.0, altitude_m=300.0)
    assert r.dtype == np.float32 and r.shape == (40, 3)
    assert hash_array(r) == REFERENCE["sky"]["radiance"]
    up = atmos.sky(np.array([[0.0, 0.0, 1.0]]), sun_elevation_deg=40.0)[0]
    assert up[2] > up[0] > 0.0, "the zenith is blue"
    # Not unit length: black.
    assert np.all(atmos.sky(np.array([[0.0, 0.0, 2.0]]))[0] == 0.0)


def test_sky_image_and_parameters():
    img = atmos.sky_image(8, 4, sun_elevation_deg=10.0)
    assert img.shape == (4, 8, 3) and np.all(img > 0.0)
    d = atmos.defaults()
    assert "rayleigh" in d and "mie" in d
    with pytest.raises(ValueError, match="bottom_radius"):
        atmos.sky(np.array([[0.0, 0.0, 1.0]]), bottom_radius_m=-1.0)
    with pytest.raises(ValueError, match="colour"):
        atmos.sky(np.array([[0.0, 0.0, 1.0]]), colour=1)
    with pytest.raises(ValueError, match="elevation"):
        atmos.sky(np.array([[0.0, 0.0, 1.0]]), sun_elevation_deg=float("nan"))


def test_zero_size_non_contiguous_and_nan_points_do_not_crash():
    assert texture.sample("terran", np.zeros((0, 3))).colour.shape == (0, 3)
    assert atmos.sky(np.zeros((0, 3))).shape == (0, 3)
    p = points3()
    wide = np.zeros((37, 6))
    wide[:, ::2] = p
    a = texture.sample("terran", wide[:, ::2]).colour  # a strided view
    assert np.array_equal(a, texture.sample("terran", p).colour)
    texture.sample("terran", np.full((2, 3), np.nan))  # unspecified values, no crash
    assert np.all(atmos.sky(np.full((1, 3), np.nan)) == 0.0)  # black
    with pytest.raises(ValueError, match="width and height"):
        texture.equirect("terran", 0, 4)


def test_planet_map_equals_the_rust_api_bit_for_bit():
    m = texture.planet("gaea", width=32, height=16)
    assert m.colour.shape == (16, 32, 3) and m.height.shape == (16, 32)
    assert hash_array(m.colour) == REF["gaea_colour"]
    assert hash_array(m.height) == REF["gaea_height"]
    d = texture.planet_defaults("gaea")
    assert d["radius_m"] == 6_371_000.0 and "rings" not in d
    # Fields laid over the preset: a smaller planet, same layers.
    small = texture.planet("selene", width=8, height=4, radius_m=1_000_000.0)
    assert small.colour.shape == (4, 8, 3)
    with pytest.raises(ValueError, match="radius_m"):
        texture.planet("selene", width=8, height=4, radius_m=-1.0)
    with pytest.raises(ValueError, match="radius_km"):
        texture.planet("selene", width=8, height=4, radius_km=1.0)
    with pytest.raises(ValueError, match="preset"):
        texture.planet("mars", width=8, height=4)
    with pytest.raises(ValueError, match="width"):
        texture.planet("selene", width=0, height=4)
    calls = []
    texture.planet("selene", width=8, height=4, progress=lambda *a: calls.append(a))
    assert calls and calls[-1][1] == calls[-1][2]
