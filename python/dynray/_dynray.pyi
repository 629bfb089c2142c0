"""Type stubs of the extension module (python/src/*.rs); docs/python.md is the guide."""

from os import PathLike
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple, TypedDict, Union

import numpy as np
import numpy.typing as npt

_Path = Union[str, "PathLike[str]"]
_Floats = npt.ArrayLike
_Interval = Union[float, npt.ArrayLike]

ACCELS: List[str]
"""Every structure name `build` accepts (the CLI's `--accel` names), brute first."""
__version__: str

class Hits(TypedDict, total=False):
    """Closest hits, one entry per ray, with trace-rays' names, dtypes and miss values."""

    t: npt.NDArray[np.float32]
    """Ray parameter of the hit; inf on a miss."""
    prim: npt.NDArray[np.int64]
    """Triangle index (row of the faces); -1 on a miss."""
    u: npt.NDArray[np.float32]
    """Barycentric weight of the triangle's second vertex; 0 on a miss."""
    v: npt.NDArray[np.float32]
    """Barycentric weight of the third vertex; 0 on a miss."""
    normal: npt.NDArray[np.float32]
    """(N, 3) unit geometric normal (p1-p0)x(p2-p0), only with normal=True; NaN on a miss."""
    point: npt.NDArray[np.float32]
    """(N, 3) hit point (1-u-v)p0 + u p1 + v p2, only with point=True; NaN on a miss."""

class Mesh:
    """An immutable triangle mesh: vertices (N, 3) float32/float64, faces (M, 3)
    int32/int64/uint32/uint64, any memory order. Raises ValueError (shape, NaN/Inf,
    index out of range, no faces) or TypeError (dtype)."""

    def __init__(self, vertices: _Floats, faces: npt.ArrayLike) -> None: ...
    @property
    def vertices(self) -> npt.NDArray[np.float32]: ...
    @property
    def faces(self) -> npt.NDArray[np.uint32]: ...
    @property
    def triangle_count(self) -> int: ...
    @property
    def vertex_count(self) -> int: ...
    @property
    def bounds(self) -> Tuple[List[float], List[float]]: ...
    def __len__(self) -> int: ...

class Scene:
    """A file read by `load`: its mesh (unshaded: triangle numbers are the file's faces),
    materials, lights, camera, image size and loader warnings."""

    @property
    def path(self) -> Path: ...
    @property
    def mesh(self) -> Mesh: ...
    @property
    def materials(self) -> List[Dict[str, Any]]: ...
    @property
    def lights(self) -> List[Dict[str, Any]]: ...
    @property
    def camera(self) -> Optional[Dict[str, Any]]: ...
    @property
    def size(self) -> Tuple[int, int]: ...
    @property
    def warnings(self) -> List[str]: ...

class Structure:
    """An acceleration structure over a Mesh (made by `build`). Queries release the GIL."""

    def intersect(
        self,
        origins: _Floats,
        directions: Optional[_Floats] = None,
        tmin: Optional[_Interval] = None,
        tmax: Optional[_Interval] = None,
        *,
        normal: bool = False,
        point: bool = False,
        threads: Optional[int] = None,
    ) -> Hits:
        """Closest hits of (N, 8) rays, or of (N, 3) origins (or one (3,) origin) and
        directions over [tmin, tmax] (defaults 0 and inf)."""
    def occluded(
        self,
        origins: _Floats,
        directions: Optional[_Floats] = None,
        tmin: Optional[_Interval] = None,
        tmax: Optional[_Interval] = None,
        *,
        threads: Optional[int] = None,
    ) -> npt.NDArray[np.bool_]:
        """True where any triangle lies on the ray within [tmin, tmax]."""
    def refit(self, vertices: _Floats, *, threads: Optional[int] = None) -> None:
        """New vertex positions, same faces (bvh, bih); NotImplementedError otherwise."""
    def stats(self) -> Dict[str, Any]: ...
    def validate(self) -> Dict[str, Any]: ...
    @property
    def memory_bytes(self) -> int: ...
    @property
    def name(self) -> str: ...
    @property
    def accel(self) -> str: ...
    @property
    def refits(self) -> bool: ...
    @property
    def mesh(self) -> Mesh: ...

def load(path: _Path, *, time: Optional[float] = None, frame: Optional[int] = None) -> Scene:
    """Any file the engine reads; OSError if unreadable, ValueError if malformed. With
    `time` or `frame`, `mesh` is posed at that instant (physics simulated), as trace-rays
    traces it."""

def build(
    mesh: Mesh,
    accel: str = "bvh",
    *,
    eye: Optional[Sequence[float]] = None,
    threads: Optional[int] = None,
    **params: Union[bool, int, float, str],
) -> Structure:
    """A structure by its --accel name ("bih", "bih:max_prims=5", "kdtree:fast") with
    **params as key=value; ValueError with the engine's message for bad names/keys."""

def render(
    scene: Union[Scene, _Path],
    width: Optional[int] = None,
    height: Optional[int] = None,
    spp: Optional[int] = None,
    integrator: str = "whitted",
    *,
    accel: str = "bvh",
    seed: int = 0,
    max_depth: Optional[int] = None,
    flat_shading: bool = False,
    time: Optional[float] = None,
    frame: Optional[int] = None,
    threads: Optional[int] = None,
) -> npt.NDArray[np.float32]:
    """(height, width, 3) float32 linear radiance, row 0 at the top: what
    `dynray render … -o x.exr` writes for the same options (physics simulated to `time`)."""

def trace_rays(
    mesh_path: _Path,
    rays_path: _Path,
    out_path: _Path,
    accel: str = "bvh",
    occluded: bool = False,
    fields: Optional[Sequence[str]] = None,
    *,
    time: Optional[float] = None,
    frame: Optional[int] = None,
    threads: Optional[int] = None,
    rows: Optional[Tuple[int, int]] = None,
) -> Dict[str, Any]:
    """`dynray trace-rays MESH --rays RAYS -o OUT` in process; returns counts and times.
    `rows=(a, b)`: only rows a..b (b exclusive), as `--rows a..b`, the archive then
    holding `rows` = [a, b, N]."""

def merge_hits(parts: Sequence[_Path], out_path: _Path) -> Dict[str, Any]:
    """`dynray merge-hits PART... -o OUT`: slice archives joined in row order into the
    archive of one run over every row; ValueError for gaps, overlaps or mixed parts."""

def accel_params(accel: str) -> Dict[str, Any]:
    """{"keys": {key: doc}, "presets": [names]} of a structure."""
