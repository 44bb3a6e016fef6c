"""Scenes (natura-render) rendered to float image arrays.

A scene is natura-render's ``SceneDesc``: TOML text with the keys of the
built-in scene (:data:`DEFAULT_SCENE_TOML`, whose comments document every
key), or a dict with the same keys nested the same way
(``{"sun": {"elevation_deg": 12.0}}``), or ``None`` for the built-in scene.
Keys left out keep the built-in scene's values. An unknown key, a value of
the wrong type or a bad value raises ``ValueError`` naming the key.

The built-in scene is large (a 2048² terrain at 1920 × 1080 with clouds and
a forest: minutes). :data:`QUICK` is a small one for trying things out, and
``quick=True`` previews any scene as the Rust examples' ``--quick`` does.
"""

from __future__ import annotations

import copy
from typing import Any, Dict, Optional, Union

import numpy as np

from natura import _native, _progress
from natura._progress import ProgressArg

__all__ = ["DEFAULT_SCENE_TOML", "QUICK", "render", "render_with_exposure", "scene_toml"]

#: The built-in scene as TOML text, with its comments (natura-render's
#: ``DEFAULT_SCENE_TOML``).
DEFAULT_SCENE_TOML: str = _native.DEFAULT_SCENE_TOML

#: A small scene over the built-in one (the Rust crate's quick-start): the
#: same 61 km world on a 64² terrain of 960 m cells, three steps of each
#: erosion, no clouds and no forest, 96 × 54 pixels at one sample. Renders in
#: about a second.
QUICK: Dict[str, Any] = {
    "terrain": {"size": 64, "cell_size_m": 960.0},
    "erosion": {"stream_power_steps": 3, "thermal_steps": 3},
    "clouds": {"enabled": False},
    "vegetation": {"enabled": False},
    "render": {"width": 96, "height": 54, "spp": 1},
}

Scene = Union[None, str, Dict[str, Any]]


def scene_toml(scene: Scene = None, *, quick: bool = False) -> str:
    """The scene with every key written out, as TOML text (parsed and
    validated as :func:`render` does); with ``quick``, its quick preview
    (see :func:`render`)."""
    return _native.scene_toml(
        copy.deepcopy(scene) if isinstance(scene, dict) else scene, quick
    )


def render_with_exposure(
    scene: Scene = None,
    *,
    width: Optional[int] = None,
    height: Optional[int] = None,
    spp: Optional[int] = None,
    seed: Optional[int] = None,
    quick: bool = False,
    progress: ProgressArg = None,
) -> "tuple[np.ndarray, float]":
    """As :func:`render`, with the exposure in stops the scene asks for
    (``render.exposure_ev``) or the automatic one (log-average luminance to
    18 % grey) that the Rust ``render_scene`` picks for its PNG."""
    cb = _progress.reporter(progress)
    try:
        return _native.render_scene_array(scene, width, height, spp, seed, quick, cb)
    finally:
        _progress.closing(cb)


def render(
    scene: Scene = None,
    *,
    width: Optional[int] = None,
    height: Optional[int] = None,
    spp: Optional[int] = None,
    seed: Optional[int] = None,
    quick: bool = False,
    progress: ProgressArg = None,
) -> np.ndarray:
    """Builds the scene's world (synthesis, erosion, atmosphere, clouds,
    forest) and renders it (the Rust ``render_scene``): the linear
    scene-referred radiance as float32 ``(height, width, 3)`` (the content
    of the EXR the ``landscape`` example writes).

    ``quick`` makes the scene's quick preview first (the Rust
    ``SceneDesc::quick``, as the examples' ``--quick``): a terrain of more
    than 256 samples a side keeps its extent on 256, erosion takes at most
    5 stream-power, 20 hydraulic and 5 thermal steps, the clouds are 4
    times coarser; the camera and the picture stay the scene's.
    ``width``, ``height``, ``spp`` and ``seed``, when given, then replace
    the scene's ``render.width``, ``render.height``, ``render.spp`` and
    ``seed``. The GIL is released while it runs; ``progress`` (``True`` for
    a tqdm bar, or a callable ``progress(stage, done, total)``) hears each
    stage: synthesis, the erosions, the atmosphere tables, the forest,
    acceleration, and the tracing (one unit per tile of pixels)."""
    return render_with_exposure(
        scene, width=width, height=height, spp=spp, seed=seed, quick=quick, progress=progress
    )[0]
