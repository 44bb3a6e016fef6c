"""Type stubs of the compiled module natura._native (see natura.noise,
natura.terrain, natura.plant and natura.ocean for the documented,
keyword-argument API)."""

import os
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

__version__: str
NOISE_BASES: List[str]
NOISE_FRACTALS: List[str]
TERRAIN_MODELS: List[str]
TERRAIN_SYNTHS: List[str]
OCEAN_SPECTRA: List[str]

def _panic_for_test(message: str) -> None: ...
def noise_points(spec: Dict[str, Any], points: np.ndarray) -> np.ndarray: ...
def noise_grid(
    spec: Dict[str, Any], shape: Sequence[int], origin: Sequence[float], step: Sequence[float]
) -> np.ndarray: ...
def noise_defaults(kind: str) -> Dict[str, Any]: ...
def noise_bound(spec: Dict[str, Any]) -> float: ...
def terrain_erode(
    model: str,
    heights: np.ndarray,
    cell_size: float,
    steps: int,
    params: Dict[str, Any],
    seed: int,
) -> np.ndarray: ...
def terrain_synth(
    method: str, nx: int, ny: int, cell_size: float, params: Dict[str, Any], seed: int
) -> np.ndarray: ...
def terrain_defaults(name: str) -> Dict[str, Any]: ...
def terrain_fill_depressions(
    heights: np.ndarray, cell_size: float
) -> Tuple[np.ndarray, np.ndarray]: ...
def terrain_flow_accumulation(heights: np.ndarray, cell_size: float, exponent: float) -> np.ndarray: ...
def terrain_strahler_order(heights: np.ndarray, cell_size: float, threshold_m2: float) -> np.ndarray: ...
def terrain_channel_network(area: np.ndarray, threshold_m2: float) -> np.ndarray: ...
def terrain_wetness(heights: np.ndarray, cell_size: float) -> np.ndarray: ...
def terrain_save(
    format: str,
    heights: np.ndarray,
    cell_size: float,
    path: Union[str, "os.PathLike[str]"],
    range: Optional[Tuple[float, float]],
    step: int,
) -> None: ...
def lsystem_derive(text: str, steps: Optional[int] = None, seed: Optional[int] = None) -> str: ...
def lsystem_mesh(
    text: str,
    steps: Optional[int] = None,
    seed: Optional[int] = None,
    params: Optional[Dict[str, Any]] = None,
) -> Dict[str, np.ndarray]: ...
def lsystem_save_glb(
    text: str,
    path: Union[str, "os.PathLike[str]"],
    steps: Optional[int] = None,
    seed: Optional[int] = None,
    params: Optional[Dict[str, Any]] = None,
) -> None: ...
def ocean_frames(
    params: Dict[str, Any],
    spectrum_spec: Dict[str, Any],
    seed: int,
    times: Sequence[float],
    foam: Optional[Dict[str, Any]] = None,
) -> Dict[str, np.ndarray]: ...
def ocean_defaults(name: str) -> Dict[str, Any]: ...
