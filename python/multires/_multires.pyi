"""Type stubs of the compiled extension (see the docstrings at run time)."""

from os import PathLike
from typing import Any, Callable, Optional, Sequence, Tuple, Union, final

import numpy as np
import numpy.typing as npt

_Path = Union[str, PathLike[str]]
_Region = npt.ArrayLike  # an index array (any integer dtype) or a boolean mask
_Vec3 = npt.ArrayLike
_Matrix = npt.ArrayLike
_Weld = Union[str, float]

__version__: str
__all__ = ["MeshError", "EditError", "RecipeError", "Mesh", "Hierarchy", "read", "icosphere", "grid", "torus", "surface_distance", "lee_drag", "disk", "blend", "submesh_pull", "submesh_scale", "submesh_rotate", "submesh_taper", "submesh_twist", "barr_taper", "barr_twist", "barr_bend", "taubin", "ffd", "blend_image", "blend_polyline", "apply_recipe", "workflow", "_collect_inputs", "_process", "_parse_shard", "_job_hash", "_output_path", "_blake3_file", "_blake3_text", "__version__"]

class MeshError(ValueError): ...
class EditError(MeshError): ...
class RecipeError(MeshError): ...

@final
class Mesh:
    @staticmethod
    def from_arrays(vertices: npt.ArrayLike, faces: npt.ArrayLike) -> Mesh: ...
    @property
    def vertices(self) -> npt.NDArray[np.float64]: ...
    @vertices.setter
    def vertices(self, value: npt.ArrayLike) -> None: ...
    @property
    def faces(self) -> npt.NDArray[np.int64]: ...
    @property
    def n_vertices(self) -> int: ...
    @property
    def n_faces(self) -> int: ...
    @property
    def n_edges(self) -> int: ...
    def write(self, path: _Path) -> None: ...
    def check(self) -> None: ...
    def info(self) -> dict[str, Any]: ...
    def welded(self, tolerance: Optional[_Weld] = None) -> Mesh: ...
    def copy(self) -> Mesh: ...
    def __copy__(self) -> Mesh: ...
    def __deepcopy__(self, _memo: Any) -> Mesh: ...

@final
class Hierarchy:
    def __new__(
        cls,
        mesh: Mesh,
        method: str = "rounds",
        target_faces: int = 2000,
        max_levels: Optional[int] = None,
        max_error: Optional[float] = None,
        detail: str = "local",
        placement: str = "midpoint",
        progress: Optional[Callable[[int, int, int], Any]] = None,
    ) -> Hierarchy: ...
    @property
    def level(self) -> Optional[int]: ...
    @property
    def coarsest_level(self) -> int: ...
    @property
    def n_levels(self) -> int: ...
    @property
    def level_face_counts(self) -> list[int]: ...
    @property
    def n_records(self) -> int: ...
    @property
    def method(self) -> str: ...
    def go_to_level(self, level: int) -> None: ...
    def refine(self) -> Mesh: ...
    @property
    def mesh(self) -> Mesh: ...
    @property
    def vertices(self) -> npt.NDArray[np.float64]: ...
    @property
    def faces(self) -> npt.NDArray[np.int64]: ...
    @property
    def input_indices(self) -> npt.NDArray[np.int64]: ...
    def set_vertices(self, vertices: npt.ArrayLike) -> None: ...
    def ancestors(self, level: int) -> npt.NDArray[np.int64]: ...
    def records(self) -> dict[str, npt.NDArray[Any]]: ...
    def info(self) -> dict[str, Any]: ...
    def save(self, path: _Path) -> None: ...
    @staticmethod
    def load(path: _Path) -> Hierarchy: ...
    def to_bytes(self) -> bytes: ...
    @staticmethod
    def from_bytes(data: bytes) -> Hierarchy: ...
    def copy(self) -> Hierarchy: ...
    def __copy__(self) -> Hierarchy: ...
    def __deepcopy__(self, _memo: Any) -> Hierarchy: ...

_Target = Union[Mesh, Hierarchy]

def icosphere(level: int) -> Mesh: ...
def grid(nx: int, ny: int, sx: float = 1.0, sy: float = 1.0) -> Mesh: ...
def torus(major: float = 1.0, minor: float = 0.3, nu: int = 32, nv: int = 16) -> Mesh: ...
def read(path: _Path, weld: Optional[_Weld] = None) -> Mesh: ...
def surface_distance(
    a: Mesh, b: Mesh, samples: int = 100000, vertices: bool = True
) -> dict[str, Any]: ...
def lee_drag(
    target: _Target,
    primitive: _Region,
    displacement: _Vec3,
    *,
    area: Optional[_Region] = None,
    disk: Optional[Tuple[int, int]] = None,
    scale: float = 0.5,
    frames: str = "global",
) -> int: ...
def disk(target: _Target, seed: int, vertex_count: int) -> npt.NDArray[np.int64]: ...
def blend(
    target: _Target,
    handle: _Region,
    fixed: _Region,
    transform: _Matrix,
    *,
    distance: str = "geodesic",
    shape: str = "smoothstep",
    refine: Optional[float] = None,
    max_new_vertices: Optional[int] = None,
) -> dict[str, int]: ...
def submesh_pull(
    target: _Target, region: _Region, offset: _Vec3, *, propagation: int = 2, falloff: str = "linear"
) -> int: ...
def submesh_scale(
    target: _Target,
    region: _Region,
    factor: float,
    *,
    centre: Optional[_Vec3] = None,
    propagation: int = 2,
    falloff: str = "linear",
) -> int: ...
def submesh_rotate(
    target: _Target,
    region: _Region,
    degrees: float,
    *,
    axis: Optional[Tuple[_Vec3, _Vec3]] = None,
    bounded: bool = False,
    propagation: int = 2,
    falloff: str = "linear",
) -> int: ...
def submesh_taper(
    target: _Target,
    region: _Region,
    factor: float,
    *,
    axis: Optional[Tuple[_Vec3, _Vec3]] = None,
    variation: Union[None, str, int, Tuple[float, float]] = None,
    propagation: int = 2,
    falloff: str = "linear",
) -> int: ...
def submesh_twist(
    target: _Target,
    region: _Region,
    degrees: float,
    *,
    axis: Optional[Tuple[_Vec3, _Vec3]] = None,
    variation: Union[None, str, int, Tuple[float, float]] = None,
    propagation: int = 2,
    falloff: str = "linear",
) -> int: ...
def barr_taper(
    target: _Target, centre: _Vec3, axis: _Vec3, start: float, end: float, factor: float,
    *, vertices: Optional[_Region] = None,
) -> None: ...
def barr_twist(
    target: _Target, centre: _Vec3, axis: _Vec3, start: float, end: float, degrees: float,
    *, vertices: Optional[_Region] = None,
) -> None: ...
def barr_bend(
    target: _Target, centre: _Vec3, axis: _Vec3, direction: _Vec3, rate: float,
    *, range: Optional[Tuple[float, float]] = None, vertices: Optional[_Region] = None,
) -> None: ...
def taubin(
    target: _Target,
    *,
    vertices: Optional[_Region] = None,
    iterations: int = 10,
    lambda_: float = 0.33,
    mu: float = ...,  # -0.34
    weights: str = "uniform",
    fix_boundary: bool = True,
) -> None: ...
def ffd(
    target: _Target,
    vertices: Optional[_Region],
    origin: _Vec3,
    x_direction: _Vec3,
    up: _Vec3,
    *,
    shape_grid: Tuple[Tuple[int, int], Tuple[int, int]] = ...,  # ((3, 3), (4, 4))
    height_grid: Tuple[Tuple[int, int], Tuple[int, int]] = ...,  # ((1, 1), (2, 2))
    margin: float = 0.1,
    translate: Optional[_Vec3] = None,
    bend: Optional[float] = None,
    twist: Optional[float] = None,
    taper: Optional[Tuple[float, float]] = None,
    scale_heights: Optional[float] = None,
) -> int: ...
def blend_image(
    image: npt.ArrayLike,
    handle: npt.ArrayLike,
    fixed: npt.ArrayLike,
    transform: _Matrix,
    *,
    grid_step: int = 4,
    shape: str = "smoothstep",
) -> npt.NDArray[Any]: ...
def blend_polyline(
    points: npt.ArrayLike,
    handle: _Region,
    fixed: _Region,
    transform: _Matrix,
    *,
    closed: bool = False,
    distance: str = "arclength",
    shape: str = "smoothstep",
    refine: Optional[float] = None,
) -> npt.NDArray[np.float64]: ...
def apply_recipe(target: _Target, recipe: str) -> list[dict[str, Any]]: ...
def workflow(
    path: _Path, *, level: int = 3, method: str = "rounds", weld: Optional[_Weld] = None
) -> Tuple[Mesh, list[dict[str, Any]]]: ...
def _collect_inputs(inputs: Sequence[str], shard: Optional[str] = None) -> list[Tuple[str, str]]: ...
def _parse_shard(shard: str) -> Tuple[int, int]: ...
def _process(
    path: str, relative: str, out: str, recipe: Optional[str] = None, format: str = "ply",
    weld: Optional[_Weld] = None, level: int = 3, method: str = "rounds",
    shard: Optional[Tuple[int, int]] = None,
) -> str: ...
def _job_hash(
    out: str, recipe: Optional[str] = None, format: str = "ply", weld: Optional[_Weld] = None,
    level: int = 3, method: str = "rounds",
) -> str: ...
def _output_path(relative: str, out: str, format: str = "ply") -> str: ...
def _blake3_file(path: _Path) -> str: ...
def _blake3_text(text: str) -> str: ...
