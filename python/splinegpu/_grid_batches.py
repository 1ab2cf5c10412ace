"""Batches of gridded interpolants: many `NdBSpline`s or `RegularGridInterpolator`s, each its
own axes, shape and points (ragged), evaluated in one call as the 1-D batches are: the result
is (values (N, ...), offsets (S + 1,)), member i's rows offsets[i]:offsets[i+1].

Every member whose method is a tensor B-spline (NdBSpline; RegularGridInterpolator's "linear",
"slinear", "cubic", "quintic") is evaluated by one call of the extension
(`_native.evaluate_tensors`), the members spread over the CPU's threads; "nearest" and "pchip"
members are evaluated one by one.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from . import _native
from ._ndbspline import NdBSpline, _orders, on_device
from ._rgi import RegularGridInterpolator


def _evaluate(splines: list, points: list, nu, extrapolate) -> tuple:
    """Each tensor spline at its points (N_i, d_i) in one native call: (values (N, m),
    offsets); NdBSpline's rules for nu and complex coefficients (the same dtype for all)."""
    orders = [_orders(nu, len(s.t)) for s in splines]
    if len({len(s.t) for s in splines}) == 1:
        on_gpu = on_device(splines, points, orders[0])
        if on_gpu is not None:
            offsets = np.concatenate([[0], np.cumsum([len(p) for p in points])])
            return np.concatenate(on_gpu), offsets.astype(np.int64)
    arguments = [(list(s.t), list(s.k), s._columns()) for s in splines]
    values, offsets = _native.evaluate_tensors(arguments, points, orders, extrapolate)
    if splines[0].c.dtype.kind == "c":
        values = np.ascontiguousarray(values).view(np.complex128)
    return values, offsets


def _points(xis, dims: list) -> list:
    """Each member's points as (N_i, d_i) float64 arrays the extension takes."""
    if len(xis) != len(dims):
        raise ValueError(f"xis: {len(xis)} arrays of points for {len(dims)} members")
    out = []
    for i, (xi, d) in enumerate(zip(xis, dims)):
        xi = np.asarray(xi, dtype=np.float64)
        if xi.shape[-1:] != (d,):
            raise ValueError(f"xis[{i}]: points of {d} coordinates expected, got shape "
                             f"{xi.shape}")
        out.append(np.require(xi.reshape(-1, d), np.float64, ["C", "A"]))
    return out


def _bounds(members: list, points: list):
    """Every member's points checked against its grid at once (as each member's `_bounds`
    would, one pass over all points): None where every point of every member lies inside
    its grid; else each member's (NaN rows or None, rows outside or None), or the first
    member's ValueError where `bounds_error`."""
    d = {len(m.grid) for m in members}
    if len(d) > 1:
        return [m._bounds(xi) for m, xi in zip(members, points)]
    counts = np.array([len(xi) for xi in points])
    every = np.concatenate(points) if len(points) > 1 else points[0]
    lo = np.repeat(np.array([[g[0] for g in m.grid] for m in members]), counts, axis=0)
    hi = np.repeat(np.array([[g[-1] for g in m.grid] for m in members]), counts, axis=0)
    inside = (lo <= every) & (every <= hi)  # False at NaN
    if inside.all():
        return None
    starts = np.concatenate([[0], np.cumsum(counts)])
    return [m._bounds(xi) if not inside[a:b].all() else (None, None)
            for m, xi, a, b in zip(members, points, starts[:-1], starts[1:])]


class NdBSplines:
    """Many `NdBSpline`s in one batch: `ts` a list of knot tuples (one per spline, each its
    own axes and lengths), `cs` the matching coefficient arrays (n_0, .., n_{d-1}, ...), with
    the same trailing shape for all; `k` one degree or one per axis, for every spline.
    `batch(xis, nu=None, extrapolate=None)` -> (values (N, ...), offsets); `batch[i]` is
    spline i."""

    def __init__(self, ts: Sequence, cs: Sequence, k, *, extrapolate=True, context=None):
        if len(ts) != len(cs):
            raise ValueError(f"cs: {len(cs)} coefficient arrays for {len(ts)} knot tuples")
        self._splines = []
        for i, (t, c) in enumerate(zip(ts, cs)):
            try:
                self._splines.append(NdBSpline(tuple(t), c, k, extrapolate=extrapolate,
                                               context=context))
            except ValueError as e:
                raise ValueError(f"splines[{i}]: {e}") from None
        trailing = {s.c.shape[len(s.t):] for s in self._splines}
        kinds = {s.c.dtype.kind for s in self._splines}
        if len(trailing) > 1 or len(kinds) > 1:
            raise ValueError(f"cs: every spline's coefficients must share their trailing "
                             f"shape and kind, got {sorted(trailing)} ({sorted(kinds)})")
        self._trailing = trailing.pop() if trailing else ()
        self.extrapolate = bool(extrapolate)
        self.context = context

    def __len__(self) -> int:
        return len(self._splines)

    def __getitem__(self, i: int) -> NdBSpline:
        return self._splines[i]

    def __call__(self, xis: Sequence, nu=None, extrapolate=None) -> tuple:
        """Spline i at xis[i] (..., d_i), derivative orders nu (one per axis, every spline of
        the same d): (values (N, ...), offsets (S + 1,))."""
        if not self._splines:
            return np.zeros((0, *self._trailing)), np.zeros(1, dtype=np.int64)
        points = _points(xis, [len(s.t) for s in self._splines])
        extrapolate = self.extrapolate if extrapolate is None else bool(extrapolate)
        values, offsets = _evaluate(self._splines, points, nu, extrapolate)
        return values.reshape((len(values), *self._trailing)), offsets


class RegularGridInterpolators:
    """Many `RegularGridInterpolator`s in one batch: `points` a list of axis tuples (one per
    grid, each its own axes and lengths), `values` the matching arrays (with the same
    trailing shape for all); `method`, `bounds_error` and `fill_value` as the single class's,
    for every grid. `batch(xis, method=None)` -> (values (N, ...), offsets); `batch[i]` is
    grid i's interpolator."""

    def __init__(self, points: Sequence, values: Sequence, method="linear", bounds_error=True,
                 fill_value=np.nan, *, context=None):
        if len(points) != len(values):
            raise ValueError(f"values: {len(values)} arrays for {len(points)} grids")
        self._members = []
        for i, (p, v) in enumerate(zip(points, values)):
            try:
                self._members.append(RegularGridInterpolator(
                    p, v, method=method, bounds_error=bounds_error, fill_value=fill_value,
                    context=context))
            except ValueError as e:
                raise ValueError(f"grids[{i}]: {e}") from None
        trailing = {m.values.shape[len(m.grid):] for m in self._members}
        if len(trailing) > 1:
            raise ValueError(f"values: every grid's values must share their trailing shape, "
                             f"got {sorted(trailing)}")
        self._trailing = trailing.pop() if trailing else ()
        self.method = method

    def __len__(self) -> int:
        return len(self._members)

    def __getitem__(self, i: int) -> RegularGridInterpolator:
        return self._members[i]

    def __call__(self, xis: Sequence, method=None) -> tuple:
        """Grid i's interpolant at xis[i] (..., d_i): (values (N, ...), offsets (S + 1,))."""
        members = self._members
        if not members:
            return np.zeros((0, *self._trailing)), np.zeros(1, dtype=np.int64)
        methods = [m._method(method, None) for m in members]
        points = _points(xis, [len(m.grid) for m in members])
        tensors: list[Any] | None = None
        if methods[0] not in ("nearest", "pchip"):
            tensors = [m._tensor(methods[0]) if methods[0] != "linear" else m._linear_tensor()
                       for m in members]
        if tensors is None or any(t is None for t in tensors):
            values = np.concatenate([m(xi, method=method).reshape(len(xi), -1)
                                     for m, xi in zip(members, points)])
            offsets = np.concatenate([[0], np.cumsum([len(xi) for xi in points])])
            return values.reshape((len(values), *self._trailing)), offsets.astype(np.int64)
        checks = _bounds(members, points)
        if methods[0] == "linear":
            points = [np.ascontiguousarray(xi[:, kept]) if len(kept) < xi.shape[1] else xi
                      for xi, (_, kept) in zip(points, tensors)]
            tensors = [spline for spline, _ in tensors]
        values, offsets = _evaluate(tensors, points, None, True)
        if checks is not None:
            # Each member's fill and NaN rules on its rows (views of the one result).
            for m, part, (nans, outside) in zip(members, np.split(values, offsets[1:-1]),
                                                checks):
                m._filled(part, nans, outside)
        return values.reshape((len(values), *self._trailing)), np.asarray(offsets,
                                                                          dtype=np.int64)
