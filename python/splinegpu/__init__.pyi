from collections.abc import Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from . import _native as _native

KIND_NAMES: tuple[str, ...]

_ArrayLike = npt.ArrayLike
_Batch = npt.NDArray[np.float64] | Sequence[_ArrayLike]

class Tessellation:
    """The samples of `Context.tessellate`: t (N,) float64; points, d1, d2 (N, D), float32 from
    the GPU backend and float64 from the CPU; curve_offsets (C + 1,) int64."""

    t: npt.NDArray[np.float64]
    points: npt.NDArray[Any]
    d1: npt.NDArray[Any] | None
    d2: npt.NDArray[Any] | None
    curve_offsets: npt.NDArray[np.int64]
    def __init__(self, t: Any, points: Any, d1: Any, d2: Any, curve_offsets: Any) -> None: ...
    def curve(self, c: int) -> Tessellation: ...
    def __len__(self) -> int: ...

class SurfaceTessellation:
    """The vertices and triangles of `Context.tessellate_surfaces`, by the NPZ's names."""

    uv: npt.NDArray[np.float64]
    points: npt.NDArray[Any]
    du: npt.NDArray[Any] | None
    dv: npt.NDArray[Any] | None
    duu: npt.NDArray[Any] | None
    duv: npt.NDArray[Any] | None
    dvv: npt.NDArray[Any] | None
    normals: npt.NDArray[Any] | None
    triangles: npt.NDArray[np.int64]
    surface_offsets: npt.NDArray[np.int64]
    triangle_offsets: npt.NDArray[np.int64]
    patch: npt.NDArray[np.int64] | None
    def __init__(self, arrays: dict[str, Any]) -> None: ...
    def arrays(self) -> dict[str, Any]: ...
    def __len__(self) -> int: ...
    def surface(self, s: int) -> dict[str, Any]: ...
    def trimesh(self, s: int | None = None) -> Any: ...

class Meshes:
    """The meshes of `Context.strokes`, `.tubes` and `.ribbons`, by the NPZ's names."""

    points: npt.NDArray[np.float64]
    t: npt.NDArray[np.float64]
    normals: npt.NDArray[np.float64] | None
    triangles: npt.NDArray[np.int64]
    curve_offsets: npt.NDArray[np.int64]
    triangle_offsets: npt.NDArray[np.int64]
    def __init__(self, arrays: dict[str, Any]) -> None: ...
    def arrays(self) -> dict[str, Any]: ...
    def __len__(self) -> int: ...
    def curve(self, c: int) -> dict[str, Any]: ...
    def trimesh(self, c: int | None = None) -> Any: ...

class ClosestPoints:
    """The answers of `Context.closest`, by the NPZ's names."""

    curve: npt.NDArray[np.int64]
    t: npt.NDArray[np.float64]
    point: npt.NDArray[np.float64]
    distance: npt.NDArray[np.float64]
    def __init__(self, arrays: dict[str, Any]) -> None: ...
    def arrays(self) -> dict[str, Any]: ...
    def __len__(self) -> int: ...

class Intersections:
    """The answers of `Context.intersections`, by the NPZ's names."""

    i: npt.NDArray[np.int64]
    j: npt.NDArray[np.int64]
    t_i: npt.NDArray[np.float64]
    t_j: npt.NDArray[np.float64]
    point: npt.NDArray[np.float64]
    tangent: npt.NDArray[np.bool_]
    overlap: npt.NDArray[np.bool_]
    def __init__(self, arrays: dict[str, Any]) -> None: ...
    def arrays(self) -> dict[str, Any]: ...
    def __len__(self) -> int: ...

class SurfacePoints:
    """The answers of `Context.closest_on_surfaces`, by the NPZ's names."""

    surface: npt.NDArray[np.int64]
    patch: npt.NDArray[np.int64]
    u: npt.NDArray[np.float64]
    v: npt.NDArray[np.float64]
    point: npt.NDArray[np.float64]
    distance: npt.NDArray[np.float64]
    def __init__(self, arrays: dict[str, Any]) -> None: ...
    def arrays(self) -> dict[str, Any]: ...
    def __len__(self) -> int: ...

class RayHits:
    """The answers of `Context.rays`, by the NPZ's names."""

    hit: npt.NDArray[np.bool_]
    surface: npt.NDArray[np.int64]
    patch: npt.NDArray[np.int64]
    u: npt.NDArray[np.float64]
    v: npt.NDArray[np.float64]
    s: npt.NDArray[np.float64]
    point: npt.NDArray[np.float64]
    normal: npt.NDArray[np.float64]
    def __init__(self, arrays: dict[str, Any]) -> None: ...
    def arrays(self) -> dict[str, Any]: ...
    def __len__(self) -> int: ...

class Context:
    """Where splines are evaluated: "auto", "gpu" or "cpu"; made once and reused."""

    def __init__(self, backend: str = "auto") -> None: ...
    def __reduce__(self) -> Any: ...
    @property
    def info(self) -> str: ...
    @property
    def backend(self) -> str: ...
    def tessellate(
        self,
        points: _Batch,
        kind: str = "catmull-rom",
        *,
        ends: str | None = None,
        tension: float | _Batch | None = None,
        bias: float | _Batch | None = None,
        continuity: float | _Batch | None = None,
        matrix: _ArrayLike | None = None,
        t: _Batch | None = None,
        start_derivative: _Batch | None = None,
        end_derivative: _Batch | None = None,
        tangents: _Batch | None = None,
        method: str | None = None,
        knots: _Batch | None = None,
        weights: _Batch | None = None,
        per_segment: int | None = None,
        at: _Batch | None = None,
        arc_length: int | None = None,
        tolerance: float | None = None,
        derivatives: int = 0,
        out: Tessellation | None = None,
    ) -> Tessellation: ...
    def closest(
        self,
        curves: _Batch,
        kind: str = "catmull-rom",
        points: npt.ArrayLike | None = None,
        **fields: Any,
    ) -> ClosestPoints: ...
    def closest_on_surfaces(
        self,
        nets: Any,
        kind: str = "bspline",
        points: npt.ArrayLike | None = None,
        **fields: Any,
    ) -> SurfacePoints: ...
    def rays(
        self,
        nets: Any,
        kind: str = "bspline",
        rays: npt.ArrayLike | None = None,
        **fields: Any,
    ) -> RayHits: ...
    def intersections(
        self,
        curves: _Batch,
        kind: str = "catmull-rom",
        pairs: str | npt.ArrayLike = "all",
        **fields: Any,
    ) -> Intersections: ...
    def strokes(
        self,
        points: _Batch,
        kind: str = "catmull-rom",
        *,
        width: float | _Batch,
        cap: str = "butt",
        join: str = "miter",
        miter_limit: float = 4.0,
        sides: int = 16,
        dash: _ArrayLike | None = None,
        dash_offset: float | None = None,
        per_segment: int | None = None,
        at: _Batch | None = None,
        arc_length: int | None = None,
        tolerance: float | None = None,
        out: Meshes | None = None,
        **fields: Any,
    ) -> Meshes: ...
    def tubes(
        self,
        points: _Batch,
        kind: str = "catmull-rom",
        *,
        radius: float | _Batch,
        sides: int | None = None,
        up: _ArrayLike | None = None,
        caps: bool = False,
        dash: _ArrayLike | None = None,
        dash_offset: float | None = None,
        per_segment: int | None = None,
        at: _Batch | None = None,
        arc_length: int | None = None,
        tolerance: float | None = None,
        out: Meshes | None = None,
        **fields: Any,
    ) -> Meshes: ...
    def ribbons(
        self,
        points: _Batch,
        kind: str = "catmull-rom",
        *,
        width: float | _Batch,
        up: _ArrayLike | None = None,
        dash: _ArrayLike | None = None,
        dash_offset: float | None = None,
        per_segment: int | None = None,
        at: _Batch | None = None,
        arc_length: int | None = None,
        tolerance: float | None = None,
        out: Meshes | None = None,
        **fields: Any,
    ) -> Meshes: ...
    def tessellate_surfaces(
        self,
        nets: _Batch,
        kind: str = "bspline",
        *,
        ends: str | tuple[str, str] | None = None,
        tension: float | None = None,
        bias: float | None = None,
        matrix: _ArrayLike | None = None,
        patches: _Batch | None = None,
        conditions: tuple[str, str] | None = None,
        u: _Batch | None = None,
        v: _Batch | None = None,
        knots_u: _Batch | None = None,
        knots_v: _Batch | None = None,
        weights: _Batch | None = None,
        per_segment: int | tuple[int, int] | None = None,
        at: _Batch | None = None,
        tolerance: float | None = None,
        derivatives: int = 0,
        normals: bool = False,
        out: SurfaceTessellation | None = None,
    ) -> SurfaceTessellation: ...

_BcType = str | tuple[tuple[int, _ArrayLike], tuple[int, _ArrayLike]]

class CubicSpline:
    """scipy.interpolate.CubicSpline's signature and meaning for the cases it covers."""

    x: npt.NDArray[np.float64]
    axis: int
    extrapolate: bool | str
    context: Context | None
    def __init__(
        self,
        x: _ArrayLike,
        y: _ArrayLike,
        axis: int = 0,
        bc_type: _BcType = "not-a-knot",
        extrapolate: bool | str | None = None,
        context: Context | None = None,
    ) -> None: ...
    def __reduce__(self) -> Any: ...
    @property
    def c(self) -> npt.NDArray[Any]: ...  # float64, or complex128 for a complex y
    def __call__(
        self, x: _ArrayLike, nu: int = 0, extrapolate: bool | str | None = None
    ) -> npt.NDArray[Any]: ...
    # A PPoly, as SciPy's: derivatives are splines of the same class, the rest as PPoly's.
    def derivative(self, nu: int = 1) -> Any: ...
    def antiderivative(self, nu: int = 1) -> Any: ...
    def integrate(
        self, a: float, b: float, extrapolate: bool | str | None = None
    ) -> npt.NDArray[Any]: ...
    def roots(self, discontinuity: bool = True, extrapolate: bool | str | None = None) -> Any: ...
    def solve(
        self, y: float = 0.0, discontinuity: bool = True, extrapolate: bool | str | None = None
    ) -> Any: ...

class CubicSplines:
    """Many cubic splines with their own knots, fitted and evaluated in one batch."""

    context: Context | None
    def __init__(
        self, xs: _Batch, ys: _Batch, bc_type: _BcType = "not-a-knot",
        context: Context | None = None,
    ) -> None: ...
    def __reduce__(self) -> Any: ...
    def __len__(self) -> int: ...
    def __call__(
        self, xs: _Batch, nu: int = 0
    ) -> tuple[npt.NDArray[Any], npt.NDArray[np.int64]]: ...
