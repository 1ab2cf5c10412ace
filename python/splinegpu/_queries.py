"""Closest points from NumPy: `Context.closest`, and what it returns, `ClosestPoints` (the
command line's NPZ arrays for a document with "queries": {"closest": ...}, by the same
names)."""

from __future__ import annotations

import numpy as np

from . import _native
from ._helpers import _aligned, _curve_fields, _curves, _float64

# The arrays of a result, by the NPZ's names, in its order.
_ARRAYS = ("curve", "t", "point", "distance")


class ClosestPoints:
    """The answers of a `Context.closest` call, one row per query point, as the command line's
    NPZ holds them: `curve` (Q,) int64, the index of the nearest curve; `t` (Q,) float64, its
    parameter there; `point` (Q, D) float64, the curve at t; `distance` (Q,) float64, its
    distance from the query point."""

    __slots__ = _ARRAYS
    curve: np.ndarray
    t: np.ndarray
    point: np.ndarray
    distance: np.ndarray

    def __init__(self, arrays: dict):
        for name in _ARRAYS:
            setattr(self, name, arrays[name])

    def arrays(self) -> dict:
        """The arrays by name: `numpy.savez(path, **result.arrays())` writes the NPZ the
        command line writes."""
        return {name: getattr(self, name) for name in _ARRAYS}

    def __len__(self) -> int:
        return len(self.t)

    def __repr__(self) -> str:
        return f"ClosestPoints({len(self.t)} queries, point {self.point.shape})"


def _queries(points) -> np.ndarray:
    """Query points as a C-ordered (Q, D) float64 array (one point may be given as (D,)),
    every coordinate finite."""
    a = _float64(points, "points")
    if a.ndim == 1:
        a = a[None, :]
    if a.ndim != 2:
        raise ValueError(f"points: must be a (Q, D) array of query points, got shape {a.shape}")
    bad = np.flatnonzero(~np.isfinite(a).all(axis=1))
    if len(bad):
        raise ValueError(f"points: query {bad[0]} has a coordinate that is not finite: "
                         f"{a[bad[0]].tolist()}")
    # Aligned too: a block unpickled from a network buffer (Dask) may not be.
    return _aligned(a, "points")


def closest(points, kind: str, queries, fields: dict) -> ClosestPoints:
    """See `Context.closest`."""
    try:
        curves = _curves(points)
    except (ValueError, TypeError) as e:
        # The curves' own points are the argument `curves` here; `points` are the queries.
        message = str(e)
        if message.startswith("points:"):
            raise type(e)("curves:" + message.removeprefix("points:")) from None
        raise
    kind_fields = _curve_fields(len(curves), **fields)
    return ClosestPoints(_native.closest_points(curves, str(kind), kind_fields,
                                                _queries(queries)))
