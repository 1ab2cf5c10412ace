from typing import Any, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

KIND_NAMES: Tuple[str, ...]

ArrayLike = npt.ArrayLike
Batch = Union[npt.NDArray[np.float64], Sequence[ArrayLike]]

class Tessellation:
    """The samples of `Context.tessellate`: t (N,) float64; points, d1, d2 (N, D), float32 from
    the GPU backend and float64 from the CPU; curve_offsets (C + 1,) int64."""

    t: npt.NDArray[np.float64]
    points: npt.NDArray[Any]
    d1: Optional[npt.NDArray[Any]]
    d2: Optional[npt.NDArray[Any]]
    curve_offsets: npt.NDArray[np.int64]
    def __init__(self, t: Any, points: Any, d1: Any, d2: Any, curve_offsets: Any) -> None: ...
    def curve(self, c: int) -> "Tessellation": ...
    def __len__(self) -> int: ...

class Context:
    """Where splines are evaluated: "auto", "gpu" or "cpu"; made once and reused."""

    def __init__(self, backend: str = "auto") -> None: ...
    @property
    def info(self) -> str: ...
    @property
    def backend(self) -> str: ...
    def tessellate(
        self,
        points: Batch,
        kind: str = "catmull-rom",
        *,
        ends: Optional[str] = None,
        tension: Optional[float] = None,
        bias: Optional[float] = None,
        matrix: Optional[ArrayLike] = None,
        t: Optional[Batch] = None,
        start_derivative: Optional[Batch] = None,
        end_derivative: Optional[Batch] = None,
        per_segment: Optional[int] = None,
        at: Optional[Batch] = None,
        arc_length: Optional[int] = None,
        tolerance: Optional[float] = None,
        derivatives: int = 0,
        out: Optional[Tessellation] = None,
    ) -> Tessellation: ...

BcType = Union[str, Tuple[Tuple[int, ArrayLike], Tuple[int, ArrayLike]]]

class CubicSpline:
    """scipy.interpolate.CubicSpline's signature and meaning for the cases it covers."""

    x: npt.NDArray[np.float64]
    axis: int
    context: Optional[Context]
    def __init__(
        self,
        x: ArrayLike,
        y: ArrayLike,
        axis: int = 0,
        bc_type: BcType = "not-a-knot",
        extrapolate: Optional[bool] = None,
        context: Optional[Context] = None,
    ) -> None: ...
    @property
    def c(self) -> npt.NDArray[Any]: ...  # float64, or complex128 for a complex y
    def __call__(self, x: ArrayLike, nu: int = 0) -> npt.NDArray[Any]: ...
    def derivative(self, nu: int = 1) -> Any: ...

class CubicSplines:
    """Many cubic splines with their own knots, fitted and evaluated in one batch."""

    context: Optional[Context]
    def __init__(
        self, xs: Batch, ys: Batch, bc_type: BcType = "not-a-knot",
        context: Optional[Context] = None,
    ) -> None: ...
    def __len__(self) -> int: ...
    def __call__(
        self, xs: Batch, nu: int = 0
    ) -> Tuple[npt.NDArray[Any], npt.NDArray[np.int64]]: ...
