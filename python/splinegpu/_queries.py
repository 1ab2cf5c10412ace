"""Queries from NumPy: `Context.closest` and `Context.intersections`, and what they return,
`ClosestPoints` and `Intersections` (the command line's NPZ arrays for a document with
"queries", by the same names)."""

from __future__ import annotations

import numpy as np

from . import _native
from ._helpers import _aligned, _curve_fields, _curves, _float64
from ._surfaces import surface_arguments

# The arrays of a result, by the NPZ's names, in its order.
_ARRAYS = ("curve", "t", "point", "distance")
_CROSSINGS = ("i", "j", "t_i", "t_j", "point", "tangent", "overlap")
_ON_SURFACES = ("surface", "patch", "u", "v", "point", "distance")
_HITS = ("hit", "surface", "patch", "u", "v", "s", "point", "normal")


class _Arrays:
    """Answers held as the command line's NPZ arrays, by their names (`_NAMES`)."""

    _NAMES: tuple = ()
    __slots__ = ()

    def __init__(self, arrays: dict):
        for name in self._NAMES:
            setattr(self, name, arrays[name])

    def arrays(self) -> dict:
        """The arrays by name: `numpy.savez(path, **result.arrays())` writes the NPZ the
        command line writes."""
        return {name: getattr(self, name) for name in self._NAMES}

    def __len__(self) -> int:
        return len(getattr(self, self._NAMES[-1]))


class ClosestPoints(_Arrays):
    """The answers of a `Context.closest` call, one row per query point, as the command line's
    NPZ holds them: `curve` (Q,) int64, the index of the nearest curve; `t` (Q,) float64, its
    parameter there; `point` (Q, D) float64, the curve at t; `distance` (Q,) float64, its
    distance from the query point."""

    _NAMES = _ARRAYS
    __slots__ = _ARRAYS
    curve: np.ndarray
    t: np.ndarray
    point: np.ndarray
    distance: np.ndarray

    def __repr__(self) -> str:
        return f"ClosestPoints({len(self.t)} queries, point {self.point.shape})"


class Intersections(_Arrays):
    """The answers of a `Context.intersections` call, as the command line's NPZ holds them,
    one row per meeting point, sorted by the pair's place (for "all", by i, then j), then t_i,
    then t_j: `i`, `j` (N,) int64, the curves (i == j: a self-intersection, t_i < t_j);
    `t_i`, `t_j` (N,) float64, their parameters; `point` (N, 2) float64, curve i at t_i;
    `tangent` (N,) bool, the curves touch with tangents parallel within 1e-6 radians;
    `overlap` (N,) bool, an end of a piece along which the curves coincide."""

    _NAMES = _CROSSINGS
    __slots__ = _CROSSINGS
    i: np.ndarray
    j: np.ndarray
    t_i: np.ndarray
    t_j: np.ndarray
    point: np.ndarray
    tangent: np.ndarray
    overlap: np.ndarray

    def __repr__(self) -> str:
        return f"Intersections({len(self.t_i)} points)"


class SurfacePoints(_Arrays):
    """The answers of `Context.closest_on_surfaces`, one row per query point: `surface` (Q,)
    int64; `patch` (Q,) int64, the patch of a patch list (-1 on a net); `u`, `v` (Q,) float64,
    the surface's parameters there (a patch list's: the patch's own); `point` (Q, D) float64;
    `distance` (Q,) float64."""

    _NAMES = _ON_SURFACES
    __slots__ = _ON_SURFACES
    surface: np.ndarray
    patch: np.ndarray
    u: np.ndarray
    v: np.ndarray
    point: np.ndarray
    distance: np.ndarray

    def __repr__(self) -> str:
        return f"SurfacePoints({len(self)} queries)"


class RayHits(_Arrays):
    """The answers of `Context.rays`, one row per ray: `hit` (Q,) bool; `surface`, `patch`
    (Q,) int64 (-1 where there is no hit, and patch -1 on nets); `u`, `v`, `s` (Q,) float64
    (NaN where there is no hit; s the distance from the origin along the ray); `point` and
    `normal` (Q, 3) float64, the unit normal Su x Sv / |Su x Sv|, not turned to the ray."""

    _NAMES = _HITS
    __slots__ = _HITS
    hit: np.ndarray
    surface: np.ndarray
    patch: np.ndarray
    u: np.ndarray
    v: np.ndarray
    s: np.ndarray
    point: np.ndarray
    normal: np.ndarray

    def __repr__(self) -> str:
        return f"RayHits({len(self)} rays, {int(self.hit.sum())} hits)"


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


def _the_curves(points):
    """The batch of curves as `tessellate` takes it, its errors naming the argument `curves`
    (`points` are the query points here)."""
    try:
        return _curves(points)
    except (ValueError, TypeError) as e:
        message = str(e)
        if message.startswith("points:"):
            raise type(e)("curves:" + message.removeprefix("points:")) from None
        raise


def _pairs(pairs, curves: int):
    """None for "all", else the pairs as a list of [i, j], each index below `curves`."""
    if isinstance(pairs, str):
        if pairs != "all":
            raise ValueError(f'pairs: must be "all" or (K, 2) curve indices, got {pairs!r}')
        return None
    a = np.asarray(pairs)
    if a.dtype.kind not in "iu" or a.ndim != 2 or a.shape[1] != 2:
        raise ValueError(f'pairs: must be "all" or (K, 2) integer curve indices, got '
                         f'{a.dtype} of shape {a.shape}')
    bad = np.flatnonzero(((a < 0) | (a >= curves)).any(axis=1))
    if len(bad):
        raise ValueError(f"pairs: pair {bad[0]} = {a[bad[0]].tolist()} names a curve that is "
                         f"not there ({curves} curves)")
    return a.astype(np.int64).tolist()


def closest(points, kind: str, queries, fields: dict, context=None) -> ClosestPoints:
    """See `Context.closest` (`context` the native context whose backend answers)."""
    curves = _the_curves(points)
    kind_fields = _curve_fields(len(curves), **fields)
    return ClosestPoints(_native.closest_points(curves, str(kind), kind_fields,
                                                _queries(queries), context))


def _rays(rays) -> np.ndarray:
    """Rays as a C-ordered (Q, 6) float64 array (one may be given as (6,)), each finite, with
    a direction that is not zero."""
    a = _float64(rays, "rays")
    if a.ndim == 1:
        a = a[None, :]
    if a.ndim != 2 or a.shape[1] != 6:
        raise ValueError(f"rays: must be a (Q, 6) array of (ox, oy, oz, dx, dy, dz), got shape "
                         f"{a.shape}")
    bad = np.flatnonzero(~np.isfinite(a).all(axis=1))
    if len(bad):
        raise ValueError(f"rays: ray {bad[0]} has a value that is not finite: {a[bad[0]].tolist()}")
    zero = np.flatnonzero((a[:, 3:] == 0).all(axis=1))
    if len(zero):
        raise ValueError(f"rays: ray {zero[0]} has a zero direction")
    return _aligned(a, "rays")


def closest_on_surfaces(nets, kind: str, queries, fields: dict,
                        context=None) -> SurfacePoints:
    """See `Context.closest_on_surfaces`."""
    nets3, kind_fields = surface_arguments(nets, **fields)
    return SurfacePoints(_native.closest_on_surfaces(nets3, str(kind), kind_fields,
                                                     _queries(queries), context))


def first_hits(nets, kind: str, rays, fields: dict, context=None) -> RayHits:
    """See `Context.rays`."""
    nets3, kind_fields = surface_arguments(nets, **fields)
    if nets3 and nets3[0].shape[2] != 3:
        raise ValueError(f"nets: rays meet 3-D surfaces, these have D = {nets3[0].shape[2]}")
    return RayHits(_native.ray_hits(nets3, str(kind), kind_fields, _rays(rays), context))


def intersections(points, kind: str, pairs, fields: dict) -> Intersections:
    """See `Context.intersections`."""
    curves = _the_curves(points)
    kind_fields = _curve_fields(len(curves), **fields)
    return Intersections(_native.intersections_of(curves, str(kind), kind_fields,
                                                  _pairs(pairs, len(curves))))
