"""Type stubs of the compiled module natura._native (see natura.noise,
natura.terrain, natura.plant, natura.ocean, natura.volume, natura.texture,
natura.atmos and natura.render for the documented, keyword-argument API)."""

import os
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

__version__: str
NOISE_BASES: List[str]
NOISE_FRACTALS: List[str]
TERRAIN_MODELS: List[str]
TERRAIN_SYNTHS: List[str]
OCEAN_SPECTRA: List[str]
TEXTURE_NAMES: List[str]
DEFAULT_SCENE_TOML: str

Progress = Optional[Callable[[str, int, int], Any]]
Baked = Tuple[np.ndarray, Tuple[float, float, float], float]

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
    progress: Progress = None,
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
def plant_ecosystem(
    heights: np.ndarray,
    cell_size: float,
    params: Dict[str, Any],
    per_species: int = 3,
    progress: Progress = None,
    wetness: Optional[np.ndarray] = None,
) -> Dict[str, Any]: ...
def ecosystem_defaults() -> Dict[str, Any]: ...
def species_preset(name: str) -> Dict[str, Any]: ...
def cloud_density(
    shape: Union[str, List[Dict[str, Any]]],
    cell: float,
    seed: int,
    params: Dict[str, Any],
    progress: Progress = None,
) -> Baked: ...
def cloud_primitives(name: str) -> List[Dict[str, Any]]: ...
def volume_render(
    density: np.ndarray,
    origin: Tuple[float, float, float],
    cell: float,
    eye: Tuple[float, float, float],
    target: Tuple[float, float, float],
    fov_deg: float,
    width: int,
    height: int,
    sun: Optional[Tuple[Tuple[float, float, float], Tuple[float, float, float]]],
    sky: Tuple[float, float, float],
    medium: Dict[str, Any],
    mode: str,
    settings: Dict[str, Any],
    progress: Progress = None,
    supersample: int = 1,
) -> np.ndarray: ...
def layer_density(
    cell: float, seed: int, params: Dict[str, Any], progress: Progress = None
) -> Baked: ...
def volume_defaults(kind: str) -> Dict[str, Any]: ...
def smoke_plume(
    cells: int, width: float, epsilon: float, steps: int, progress: Progress = None
) -> Tuple[np.ndarray, np.ndarray, float, float]: ...

class SmokeSolver:
    def __init__(
        self, dims: Tuple[int, int, int], cell: float, params: Optional[Dict[str, Any]] = None
    ) -> None: ...
    def add_source(self, source: Dict[str, Any]) -> None: ...
    def add_obstacle(self, obstacle: Dict[str, Any]) -> None: ...
    def step(
        self,
        dt: float,
        steps: int = 1,
        force: Optional[List[np.ndarray]] = None,
        progress: Progress = None,
    ) -> Dict[str, Any]: ...
    @property
    def density(self) -> np.ndarray: ...
    @property
    def temperature(self) -> np.ndarray: ...
    def set_density(self, a: np.ndarray) -> None: ...
    def set_temperature(self, a: np.ndarray) -> None: ...
    @property
    def velocity(self) -> List[np.ndarray]: ...
    @property
    def solid(self) -> np.ndarray: ...
    @property
    def time(self) -> float: ...
    @property
    def dims(self) -> Tuple[int, int, int]: ...
    @property
    def cell(self) -> float: ...
    @property
    def params(self) -> Dict[str, Any]: ...

def vdb_write(
    path: Union[str, "os.PathLike[str]"],
    grids: Dict[str, np.ndarray],
    origin: Tuple[float, float, float],
    cell: float,
) -> None: ...
def vdb_read(path: Union[str, "os.PathLike[str]"]) -> Dict[str, Baked]: ...
def texture_sample(
    name: str, points: np.ndarray, footprint: float, params: Dict[str, Any]
) -> Tuple[np.ndarray, np.ndarray, np.ndarray]: ...
def texture_defaults(name: str) -> Dict[str, Any]: ...
def git_filter(
    image: np.ndarray, params: Dict[str, Any], progress: Progress = None
) -> np.ndarray: ...
def git_filter_defaults() -> Dict[str, Any]: ...
def colour_ellipsoid(colours: np.ndarray) -> Dict[str, Any]: ...
def sky_radiance(
    directions: np.ndarray,
    sun_elevation_deg: float,
    sun_azimuth_deg: float,
    altitude_m: float,
    params: Dict[str, Any],
) -> np.ndarray: ...
def atmosphere_defaults() -> Dict[str, Any]: ...
def planet_equirect(
    preset: str, width: int, height: int, params: Dict[str, Any], progress: Progress = None
) -> Tuple[np.ndarray, np.ndarray]: ...
def planet_defaults(preset: str) -> Dict[str, Any]: ...
def scene_toml(scene: Union[None, str, Dict[str, Any]] = None, quick: bool = False) -> str: ...
def render_scene_array(
    scene: Union[None, str, Dict[str, Any]] = None,
    width: Optional[int] = None,
    height: Optional[int] = None,
    spp: Optional[int] = None,
    seed: Optional[int] = None,
    quick: bool = False,
    progress: Progress = None,
) -> Tuple[np.ndarray, float]: ...
