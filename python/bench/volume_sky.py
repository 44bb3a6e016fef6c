"""The fast mode against the reference path tracer under a uniform sky
alone and under a sun and the sky, on a ball of constant density (a 16³
grid, 32 × 32 pixels, two reference seeds of 128 paths): prints fast ÷
reference over the pixels that see the ball.

    python python/bench/volume_sky.py
"""

import numpy as np

from natura import volume


def ball(n=16):
    c = (np.arange(n, dtype=np.float32) + 0.5) / n * 2.0 - 1.0
    z, y, x = np.meshgrid(c, c, c, indexing="ij")
    d = np.where(x * x + y * y + z * z < 1.0, 1.0, 0.0).astype(np.float32)
    return volume.Volume(d, (-1.0, -1.0, -1.0), 2.0 / n)


def lum(a):
    return (a * np.array([0.2126, 0.7152, 0.0722])).sum(axis=2)


def main():
    b = ball()
    view = dict(eye=(0.0, -4.0, 0.5), target=(0.0, 0.0, 0.0), fov_deg=40.0, width=32, height=32)
    sky = np.array([0.25, 0.35, 0.55], dtype=np.float32)
    for sun in [None, (0.4, -0.6, 0.7)]:
        for phase in [{"henyey_greenstein": 0.0}, {"henyey_greenstein": 0.6},
                      {"cloud": {"diameter_um": 10.0}}]:
            for tau in [2.0, 16.0]:
                medium = {"extinction": tau / 2.0, "albedo": 0.99, "phase": phase}
                ref = sum(
                    volume.render(b, medium=medium, sun_direction=sun, mode="reference",
                                  settings={"samples_per_pixel": 128, "seed": s}, **view)
                    for s in (1, 2)) / 2
                seen = np.abs(ref - sky).sum(axis=2) > 1e-3
                fast = volume.render(b, medium=medium, sun_direction=sun, **view)
                ratio = lum(fast)[seen].sum() / lum(ref)[seen].sum()
                print(f"sun {'none' if sun is None else 'behind'}  {phase}  tau {tau:4.1f}  "
                      f"fast / reference {ratio:.3f}")


if __name__ == "__main__":
    main()
