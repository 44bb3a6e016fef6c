"""natura's Python benchmark: 2-D fBm (8 octaves, 1024 x 1024 grid, one
thread) against the registry's Python noise packages in the same process,
the per-call overhead, erosion from Python against the same call from Rust,
the wheel's size and its install-and-import time.

    python bench/bench.py --wheel WHEEL [--repo DIR]

Peers that are not installed are reported as such. Each timing is the best
of several runs (wall clock); peers slower than a second per grid are timed
on a smaller grid and scaled by the point count (said in the output).
"""

import argparse
import inspect
import os
import pathlib
import subprocess
import sys
import tempfile
import time
import timeit

import numpy as np

N = 1024
OCTAVES = 8
FREQ = 1.0 / 128.0  # 8 cycles of the base octave across the grid


def best(f, repeats=3):
    t = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        f()
        t.append(time.perf_counter() - t0)
    return min(t)


def scaled(make, n_full=N):
    """Seconds for an n_full^2 grid: timed on the full grid if one run takes
    under about a second (estimated from a 64^2 grid), else on the largest
    power-of-two grid that does, scaled by the point count."""
    t64 = best(make(64), repeats=1)
    n = n_full
    while n > 64 and t64 * (n / 64) ** 2 > 1.0:
        n //= 2
    t = best(make(n), repeats=3 if n == n_full else 2)
    return t * (n_full / n) ** 2, n


def bench_natura():
    import natura

    def run(n):
        return lambda: natura.noise.fbm_grid(
            (n, n), step=(FREQ, FREQ), octaves=OCTAVES, lacunarity=2.0
        )

    return scaled(run)


def bench_noise():
    import noise

    def run(n):
        def f():
            p = noise.pnoise2
            for j in range(n):
                y = j * FREQ
                for i in range(n):
                    p(i * FREQ, y, octaves=OCTAVES)

        return f

    return scaled(run)


def bench_opensimplex():
    import opensimplex

    opensimplex.seed(1)

    def run(n):
        xs = np.arange(n) * FREQ

        def f():
            total = np.zeros((n, n))
            amp, fr = 1.0, 1.0
            for _ in range(OCTAVES):
                total += amp * opensimplex.noise2array(xs * fr, xs * fr)
                amp *= 0.5
                fr *= 2.0
            return total

        return f

    return scaled(run)


def bench_fastnoiselite():
    from pyfastnoiselite.pyfastnoiselite import FastNoiseLite, FractalType, NoiseType

    g = FastNoiseLite(1)
    g.noise_type = NoiseType.NoiseType_Perlin
    g.fractal_type = FractalType.FractalType_FBm
    g.fractal_octaves = OCTAVES
    g.frequency = 1.0

    def run(n):
        xs = np.arange(n, dtype=np.float32) * np.float32(FREQ)
        gx, gy = np.meshgrid(xs, xs)
        coords = np.ascontiguousarray(np.stack([gx.ravel(), gy.ravel()]), dtype=np.float32)
        return lambda: g.gen_from_coords(coords)

    return scaled(run)


def bench_fastnoisesimd():
    import pyfastnoisesimd as fns

    # pyfastnoisesimd 0.4.2 calls np.product, which numpy 2 removed (np.prod
    # is the same function): restore the alias so the package runs.
    if not hasattr(np, "product"):
        np.product = np.prod
    g = fns.Noise(numWorkers=1)
    g.noiseType = fns.NoiseType.PerlinFractal
    g.fractal.fractalType = fns.FractalType.FBM
    g.fractal.octaves = OCTAVES
    g.frequency = FREQ

    def run(n):
        return lambda: g.genAsGrid([1, n, n])

    return scaled(run)


def bench_vnoise():
    import vnoise

    v = vnoise.Noise(1)

    def run(n):
        xs = np.arange(n) * FREQ
        return lambda: v.noise2(xs, xs, octaves=OCTAVES, grid_mode=True)

    return scaled(run)


PEERS = {
    "noise": bench_noise,
    "opensimplex": bench_opensimplex,
    "pyfastnoiselite": bench_fastnoiselite,
    "pyfastnoisesimd": bench_fastnoisesimd,
    "vnoise": bench_vnoise,
}


def overhead():
    import natura
    from natura import _native

    one = np.zeros((1, 2))
    n = 20000
    per = {}
    per["natura.noise.perlin, 1 point"] = min(
        timeit.repeat(lambda: natura.noise.perlin(one), number=n, repeat=5)
    ) / n
    per["natura.noise.fbm, 1 point"] = min(
        timeit.repeat(lambda: natura.noise.fbm(one), number=n, repeat=5)
    ) / n
    spec = {"kind": "perlin"}
    per["natura._native.noise_points, 1 point"] = min(
        timeit.repeat(lambda: _native.noise_points(spec, one), number=n, repeat=5)
    ) / n
    per["(numpy: np.sin on 1 element, for scale)"] = min(
        timeit.repeat(lambda: np.sin(one), number=n, repeat=5)
    ) / n
    # Every point function of natura.noise (those taking a coordinate array
    # alone), each with its defaults: the slowest is the one the target holds.
    slowest = ("", 0.0)
    for name in natura.noise.__all__:
        f = getattr(natura.noise, name)
        if name.endswith("_grid") or not inspect.isfunction(f):
            continue
        try:
            f(one)
        except TypeError:
            continue  # needs more than the points
        t = min(timeit.repeat(lambda: f(one), number=n, repeat=5)) / n
        if t > slowest[1]:
            slowest = (name, t)
    per[f"slowest point function: natura.noise.{slowest[0]}"] = slowest[1]
    return per


def fnv(data):
    h = 0xCBF29CE484222325
    for b in data:
        h = ((h ^ b) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


def erosion(repo, model="hydraulic", size=1024, steps=10, repeats=3):
    """Best time of the same erosion from Python and from Rust (the example
    erosion_timing), the runs interleaved so both see the same machine load."""
    import natura

    exe = pathlib.Path(repo) / "target/release/examples/erosion_timing"
    if not exe.exists():
        subprocess.run(
            ["cargo", "build", "--release", "-p", "natura-python", "--example", "erosion_timing"],
            cwd=repo,
            check=True,
        )
    start = natura.terrain.spectral((size, size), cell_size=10.0, seed=1)
    f = getattr(natura.terrain, "erode_" + model)
    t_py = t_rust = float("inf")
    same = True
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = f(start, cell_size=10.0, steps=steps)
        t_py = min(t_py, time.perf_counter() - t0)
        res = subprocess.run(
            [str(exe), model, str(size), str(steps), "1"],
            check=True,
            capture_output=True,
            text=True,
        ).stdout.split()
        t_rust = min(t_rust, float(res[0]))
        same = same and fnv(out.astype("<f4").tobytes()) == int(res[1])
    return t_py, t_rust, same


def wheel_install(wheel):
    size = os.path.getsize(wheel)
    with tempfile.TemporaryDirectory() as d:
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-m", "venv", d + "/v"], check=True)
        t_venv = time.perf_counter() - t0
        py = d + "/v/bin/python"
        t0 = time.perf_counter()
        subprocess.run(
            [py, "-m", "pip", "install", "-q", "--disable-pip-version-check", wheel],
            check=True,
        )
        t_pip = time.perf_counter() - t0
        t0 = time.perf_counter()
        subprocess.run([py, "-c", "import natura"], check=True)
        t_import = time.perf_counter() - t0
    return size, t_venv, t_pip, t_import


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--wheel", required=True)
    ap.add_argument("--repo", default=str(pathlib.Path(__file__).resolve().parents[2]))
    ap.add_argument("--skip-erosion", action="store_true")
    a = ap.parse_args()

    print(f"2-D fBm, {OCTAVES} octaves, {N}x{N} grid, one thread (best wall time):")
    t_nat, _ = bench_natura()
    print(f"  natura            {t_nat * 1e3:9.1f} ms")
    fastest = None
    for name, f in PEERS.items():
        try:
            t, n = f()
        except ImportError as e:
            print(f"  {name:17s} not installed ({e})")
            continue
        note = "" if n == N else f" (timed on {n}x{n}, scaled)"
        print(f"  {name:17s} {t * 1e3:9.1f} ms  natura is {t / t_nat:7.1f}x faster{note}")
        if fastest is None or t < fastest[1]:
            fastest = (name, t)
    if fastest:
        print(f"  fastest peer: {fastest[0]}, ratio {fastest[1] / t_nat:.1f}x (target >= 10x)")

    print("\nper-call overhead (target <= 2 us):")
    for k, v in overhead().items():
        print(f"  {k:42s} {v * 1e6:6.2f} us")

    if not a.skip_erosion:
        t_py, t_rust, same = erosion(a.repo)
        print("\nerosion (Musgrave hydraulic, 1024x1024, 10 steps, best of 3, interleaved):")
        print(f"  from Python {t_py:.3f} s, from Rust {t_rust:.3f} s, "
              f"Python/Rust = {t_py / t_rust:.3f} (target <= 1.05); same result: {same}")

    size, t_venv, t_pip, t_import = wheel_install(a.wheel)
    print(f"\nwheel: {size / 1e6:.2f} MB (target <= 15 MB)")
    print(f"  fresh venv {t_venv:.2f} s; pip install of the wheel (numpy from the pip cache) "
          f"{t_pip:.2f} s; python -c 'import natura' {t_import:.2f} s; "
          f"install + import {t_pip + t_import:.2f} s (target <= 2 s)")


if __name__ == "__main__":
    main()
