"""natura.noise: values equal to the Rust API's, defaults equal to the Rust
`Params`' defaults, argument checks."""

import inspect

import numpy as np
import pytest

import natura
from natura import _native, noise
from conftest import REFERENCE, hash_array, points2, points3

ALL = _native.NOISE_BASES + _native.NOISE_FRACTALS
NO_SEED = ("sine", "checkerboard")


def seeded(kind):
    """The keyword arguments of tests/reference.rs's instance of `kind` (seed 7)."""
    return {} if kind in NO_SEED else {"seed": 7}


@pytest.mark.parametrize("kind", ALL)
def test_values_equal_the_rust_api_bit_for_bit(kind):
    ref = REFERENCE["noise"][kind]
    f, grid = getattr(noise, kind), getattr(noise, kind + "_grid")
    kw = seeded(kind)
    g2 = grid((9, 17), origin=(0.3, -1.2), step=(0.37, 0.29), **kw)
    assert g2.dtype == np.float32 and g2.shape == (9, 17)
    assert hash_array(g2) == ref["grid2"]
    g3 = grid((3, 5, 11), origin=(-0.7, 0.4, 2.5), step=(0.41, 0.23, 0.5), **kw)
    assert g3.shape == (3, 5, 11)
    assert hash_array(g3) == ref["grid3"]
    assert hash_array(f(points2(), **kw)) == ref["points2"]
    assert hash_array(f(points3(), **kw)) == ref["points3"]


def test_non_default_parameters_and_a_basis_object():
    ref = REFERENCE["noise"]["fbm_worley_f2_minus_f1"]
    kw = dict(
        basis=noise.Worley(seed=3, feature="f2_minus_f1"), h=0.9, octaves=5.5, frequency=0.5
    )
    g2 = noise.fbm_grid((9, 17), origin=(0.3, -1.2), step=(0.37, 0.29), **kw)
    assert hash_array(g2) == ref["grid2"]
    assert hash_array(noise.fbm(points3(), **kw)) == ref["points3"]
    # The Rust Fbm over a shared `dyn Field` Perlin basis gives the same values.
    assert REFERENCE["noise"]["fbm_dyn_perlin"] == REFERENCE["noise"]["fbm"]


@pytest.mark.parametrize("kind", ALL)
def test_python_defaults_are_the_rust_defaults(kind):
    rust = _native.noise_defaults(kind)
    sig = inspect.signature(getattr(noise, kind))
    py = {k: p.default for k, p in sig.parameters.items() if k not in ("points", "seed")}
    assert py == {k: v for k, v in rust.items() if k != "seed"}
    grid_sig = inspect.signature(getattr(noise, kind + "_grid"))
    for k, p in sig.parameters.items():
        if k != "points":
            assert grid_sig.parameters[k].default == p.default
    if "seed" in rust:
        assert sig.parameters["seed"].default == rust["seed"]


def test_float32_and_float64_points_and_any_shape():
    p = points3()
    a = noise.perlin(p)
    b = noise.perlin(p.astype(np.float32))
    assert np.array_equal(b, noise.perlin(p.astype(np.float32).astype(np.float64)))
    assert a.shape == (37,)
    c = noise.fbm(p[:36].reshape(2, 3, 6, 3))
    assert c.shape == (2, 3, 6)
    assert np.array_equal(c.reshape(-1), noise.fbm(p[:36]))


def test_non_contiguous_points_give_the_values_of_their_copy():
    p = np.asfortranarray(points2())
    assert not p.flags["C_CONTIGUOUS"]
    assert np.array_equal(noise.fbm(p), noise.fbm(np.ascontiguousarray(p)))
    big = np.zeros((37, 5))
    big[:, ::2][:, :2] = points2()
    strided = big[:, ::2][:, :2]
    assert np.array_equal(noise.ridged_multifractal(strided), noise.ridged_multifractal(points2()))
    rev = points3()[::-1]
    assert np.array_equal(noise.perlin(rev), noise.perlin(points3())[::-1])


def test_zero_size_and_nan_points():
    assert noise.fbm(np.zeros((0, 2))).shape == (0,)
    assert noise.perlin(np.zeros((4, 0, 3))).shape == (4, 0)
    v = noise.fbm(np.array([[np.nan, 0.0], [0.5, 0.25]]))
    assert np.isnan(v[0]) and np.isfinite(v[1])
    v = noise.perlin(np.array([[np.nan, 0.0, 1.0], [np.inf, 0.0, 1.0]]))
    assert v.shape == (2,)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(lacunarity=1.0), "lacunarity"),
        (dict(octaves=0.0), "octaves"),
        (dict(octaves=65.0), "octaves"),
        (dict(frequency=-1.0), "frequency"),
        (dict(h=float("nan")), "h"),
        (dict(convention="beta"), "convention"),
    ],
)
def test_bad_spectral_values_raise_value_error_naming_them(kwargs, name):
    with pytest.raises(ValueError, match=name):
        noise.fbm(points2(), **kwargs)


def test_worley_seed_tables():
    # MojoWorld's seed tables: denser tables give smaller cells (F1 about
    # n^(-1/2) in 2-D), deterministic, and the default is one point a cell.
    p = np.stack(np.meshgrid(np.linspace(0, 40, 120), np.linspace(0, 40, 120)), -1).reshape(-1, 2)
    one = noise.worley(p, seed=3)
    assert np.array_equal(one, noise.worley(p, seed=3, feature_points="one_per_cell"))
    four = noise.worley(p, seed=3, feature_points="poisson", density=4.0)
    assert np.array_equal(four, noise.worley(p, seed=3, feature_points="poisson", density=4.0))
    assert 0.35 < four.mean() / one.mean() < 0.7
    for table in ("variable", "gaussian"):
        v = noise.worley(p, seed=3, feature_points=table, density=4.0)
        assert np.all(np.isfinite(v)) and not np.array_equal(v, four)
    g = noise.worley_grid((8, 8), seed=3, feature_points="gaussian", density=2.0)
    assert g.shape == (8, 8) and np.all(np.isfinite(g))


def test_bad_parameters_of_bases_and_fractals_name_them():
    with pytest.raises(ValueError, match="jitter"):
        noise.worley(points2(), jitter=1.5)
    with pytest.raises(ValueError, match="density"):
        noise.worley(points2(), feature_points="poisson", density=0.0)
    with pytest.raises(ValueError, match="feature_points"):
        noise.worley(points2(), feature_points="hexagonal")
    with pytest.raises(ValueError, match="density"):
        noise.sparse_convolution(points2(), density=17)
    with pytest.raises(ValueError, match="threshold"):
        noise.hetero_terrain(points2(), threshold=0.0)
    with pytest.raises(ValueError, match="offset"):
        noise.hybrid_multifractal(points2(), offset=1e9)
    with pytest.raises(ValueError, match="fade"):
        noise.perlin(points2(), fade="linear")
    with pytest.raises(ValueError, match="basis"):
        noise.vl_noise(points2(), basis="value")
    with pytest.raises(ValueError, match="kind"):
        noise.fbm(points2(), basis="nope")
    with pytest.raises(TypeError, match="seed"):
        noise.perlin(points2(), seed=1.5)
    with pytest.raises(ValueError, match="seed"):
        noise.perlin(points2(), seed=-1)
    with pytest.raises(TypeError, match="octaves"):
        noise.fbm(points2(), octaves="8")
    with pytest.raises(TypeError, match="basis"):
        noise.fbm(points2(), basis=3)


def test_unknown_parameters_are_refused():
    with pytest.raises(TypeError, match="octave"):
        noise.fbm(points2(), octave=3)
    with pytest.raises(TypeError, match="'colour'"):
        _native.noise_points({"kind": "perlin", "colour": 1}, points2())
    basis = noise.Perlin(seed=1)
    basis.params["x"] = 1
    with pytest.raises(TypeError, match="basis: unknown parameter 'x'"):
        noise.fbm(points2(), basis=basis)


def test_points_of_wrong_dtype_or_shape_name_the_argument():
    with pytest.raises(TypeError, match="points.*float32 or float64"):
        noise.fbm(np.zeros((4, 2), dtype=np.int64))
    with pytest.raises(TypeError, match="points.*numpy array"):
        noise.fbm([[0.0, 0.0]])
    with pytest.raises(ValueError, match=r"points must have shape \(\.\.\., 2\)"):
        noise.fbm(np.zeros((4, 4)))
    with pytest.raises(ValueError, match="points"):
        noise.fbm(np.zeros(()))


def test_grid_arguments_are_checked():
    with pytest.raises(ValueError, match="shape"):
        noise.fbm_grid((4,))
    with pytest.raises(ValueError, match="origin"):
        noise.fbm_grid((4, 4), origin=(0.0, 0.0, 0.0))
    with pytest.raises(ValueError, match="step"):
        noise.fbm_grid((4, 4), step=(1.0,))
    with pytest.raises(ValueError, match="lattice"):
        noise.fbm_grid((0, 4))
    with pytest.raises(ValueError, match="lattice"):
        noise.fbm_grid((4, 4), step=(float("nan"), 1.0))


def test_grid_rows_are_y_and_columns_x():
    g = noise.perlin_grid((3, 4), origin=(0.5, 0.25), step=(0.3, 0.7), seed=2)
    x = 0.5 + 0.3 * 2
    y = 0.25 + 0.7 * 1
    at = noise.perlin(np.array([[x, y]]), seed=2)[0]
    assert abs(float(g[1, 2]) - float(at)) < 1e-5


def test_package_exports():
    assert natura.__version__ == _native.__version__
    for kind in ALL:
        assert kind in noise.__all__ and kind + "_grid" in noise.__all__
        assert getattr(noise, kind).__doc__
