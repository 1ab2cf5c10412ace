"""Every batch class of `splinegpu.interpolate` and the fits that make them: many splines, each
its own knots (ragged), fitted and evaluated in one call.

One-dimensional batches (`CubicSplines`, `CubicHermiteSplines`, `PchipInterpolators`,
`Akima1DInterpolators`, `BSplines`, `PPolys`; `make_interp_splines`, `make_smoothing_splines`,
`make_lsq_splines`, `make_splreps`, `make_splpreps`): called with one array of x per spline,
they return (values (N, m), offsets (S + 1,)), spline i's values rows offsets[i]:offsets[i+1].

Gridded batches (`NdBSplines`, `RegularGridInterpolators`): many `NdBSpline`s or
`RegularGridInterpolator`s, each its own axes, shape and points (ragged), evaluated in one call
as the 1-D batches are: (values (N, ...), offsets (S + 1,)), member i's rows
offsets[i]:offsets[i+1].

Every member whose method is a tensor B-spline (NdBSpline; RegularGridInterpolator's "linear",
"slinear", "cubic", "quintic") is evaluated by one call of the extension
(`_native.evaluate_tensors`), the members spread over the CPU's threads; "nearest" and "pchip"
members are evaluated one by one.
"""

from __future__ import annotations

import operator
from collections.abc import Sequence
from typing import Any

import numpy as np

from . import _bspl, _fitpack_repro, _lsq, _native, _smoothing
from ._bsplines import BSpline, interp_bc, interp_coefficients
from ._context import Context, default_context
from ._cubic import bc_of, piece_tables, restore
from ._helpers import (
    _aligned,
    _end_to_end,
    _extrapolate,
    _flat,
    _float64,
    _Laid,
    _natural,
    _order,
    _stacked,
)
from ._ndbspline import NdBSpline, derivative_orders, on_device
from ._ppoly import integrals, solved
from ._rgi import RegularGridInterpolator


class _Batch:
    """Many splines with their own knots, fitted and evaluated in one batch: `xs` a list of
    1-D knot arrays (or a 2-D array, one row per spline), `ys` matching (n_i, m) arrays (or an
    (S, n, m) array). Calling with one array of x per spline returns (values (N, m),
    offsets (S + 1,)): spline i's values are rows offsets[i]:offsets[i+1], every spline in one
    call on the context. Its subclasses are the constructors."""

    context: Context | None
    _native: Any

    @staticmethod
    def _inputs(xs, ys, name: str = "ys", xname: str = "xs"):
        """xs and ys as the extension takes them, and ys' trailing shape (its values per x)."""
        xs, ys = _stacked(xs, xs), _stacked(ys, ys)
        if isinstance(xs, np.ndarray) and xs.ndim == 2:
            xs = _aligned(xs, xname)
        else:
            xs = [_flat(x, xname) for x in xs]
        # One (S, n, m) array, or a list of (n_i, m) arrays.
        ys2: Any
        if isinstance(ys, np.ndarray) and ys.ndim >= 2:
            trailing = ys.shape[2:]
            ys2 = _aligned(_float64(ys, name).reshape(ys.shape[0], ys.shape[1], -1), name)
        else:
            ys = [_float64(y, name) for y in ys]
            trailing = ys[0].shape[1:] if ys else ()
            for i, y in enumerate(ys):
                if y.ndim == 0 or y.shape[1:] != trailing:
                    raise ValueError(f"{name}[{i}]: every spline's values must have the shape "
                                     f"(n_i,) + {trailing}, got {y.shape}")
            width = int(np.prod(trailing, dtype=np.int64))
            for i, y in enumerate(ys):
                if len(y) == 0:
                    raise ValueError(f"{name}[{i}]: a series of no values")
            ys2 = [_aligned(y.reshape(len(y), width), name) for y in ys]
        return xs, ys2, trailing

    def __reduce__(self):
        # As a single spline's: the fitted tables bit for bit, the context as its backend.
        attributes = {k: v for k, v in self.__dict__.items() if k != "_native"}
        return (restore, (type(self), attributes, self._native.state()))

    def __len__(self) -> int:
        return len(self._native)

    # The single class's `extrapolate` default, which `solve`, `roots` and `integrate` take.
    _extrapolates: bool | str = True
    # Whether `integrate` with extrapolate False takes the splines as zero outside their knots
    # (BSpline's rule) rather than giving NaN (PPoly's).
    _zero_outside = False

    def solve(self, y=0.0, discontinuity: bool = True, extrapolate=None):
        """Every spline's x where it equals y, as the single class's `solve` finds them, all
        splines' pieces at once: (roots (R,), offsets (S + 1,)), spline i's roots in
        roots[offsets[i]:offsets[i+1]] (NaN after the start of a piece equal to y
        everywhere). For splines of one value per x."""
        mode = bool(self._extrapolates if extrapolate is None else _extrapolate(extrapolate))
        y, discontinuity = float(y), bool(discontinuity)
        return solved(self._native.solve(y, discontinuity, mode), y)

    def roots(self, discontinuity: bool = True, extrapolate=None):
        """`solve(0, ...)`."""
        return self.solve(0.0, discontinuity, extrapolate)

    def integrate(self, a, b, extrapolate=None) -> np.ndarray:
        """Every spline's integral from a to b (each a number for all splines, or one per
        spline), as the single class's `integrate` answers, all splines' pieces at once:
        shape (S, m). `extrapolate` None (the single class's default), True, False (NaN where
        a or b lies outside the spline's knots) or "periodic"."""
        c, start, end, offsets = self._native.pieces()
        splines = len(offsets) - 1
        limits = []
        for name, value in (("a", a), ("b", b)):
            value = _float64(value, name)
            if value.ndim > 1 or value.size not in (1, splines):
                raise ValueError(f"{name}: must be a number or one per spline ({splines}), got "
                                 f"shape {value.shape}")
            limits.append(np.broadcast_to(value.reshape(-1), (splines,)))
        mode = self._extrapolates if extrapolate is None else _extrapolate(extrapolate)
        if mode is False and self._zero_outside:
            lo, hi = start[offsets[:-1]], end[offsets[1:] - 1]
            limits = [np.clip(limit, lo, hi) for limit in limits]
            mode = True
        return integrals(c, start, end, offsets, limits[0], limits[1], mode)

    def __call__(self, xs: Sequence[Any], nu: int = 0):
        """Spline i at xs[i] (a list of arrays, or a (S, k) array), derivative nu (0 to 2)
        -> (values, offsets). Every x must lie within its spline's knots."""
        xs = _stacked(xs, xs)
        if isinstance(xs, np.ndarray) and xs.ndim == 2:
            flat = _aligned(xs, "xs")
        else:
            flat = [_flat(x, "xs") for x in xs]
        ctx = self.context or default_context()
        return self._native.evaluate(ctx._native, flat, _order("nu", nu, 2))


class CubicSplines(_Batch):
    """Many `CubicSpline`s (any `bc_type` form, the same for all) in one batch; see `_Batch`."""

    def __init__(self, xs, ys, bc_type="not-a-knot", context: Context | None = None):
        xs, ys2, trailing = self._inputs(xs, ys)
        name, start, end = bc_of(bc_type, trailing, broadcast=True)
        self._native = _native.fit(xs, ys2, name, start, end)
        self.context = context
        if name == "periodic":
            self._extrapolates = "periodic"


class CubicHermiteSplines(_Batch):
    """Many `CubicHermiteSpline`s in one batch: `dydxs` shaped as `ys`; see `_Batch`."""

    def __init__(self, xs, ys, dydxs, context: Context | None = None):
        xs, ys2, _ = self._inputs(xs, ys)
        _, slopes, _ = self._inputs(xs, dydxs, "dydxs")
        self._native = _native.fit_hermite(xs, ys2, "given", slopes)
        self.context = context


class PchipInterpolators(_Batch):
    """Many `PchipInterpolator`s in one batch; see `_Batch`."""

    def __init__(self, xs, ys, context: Context | None = None):
        xs, ys2, _ = self._inputs(xs, ys)
        self._native = _native.fit_hermite(xs, ys2, "pchip", None)
        self.context = context


class Akima1DInterpolators(_Batch):
    """Many `Akima1DInterpolator`s (one `method` for all) in one batch; see `_Batch`."""

    _extrapolates = False

    def __init__(self, xs, ys, *, method: str = "akima", context: Context | None = None):
        if method not in ("akima", "makima"):
            raise ValueError(f"method: must be \"akima\" or \"makima\", got {method!r}")
        xs, ys2, _ = self._inputs(xs, ys)
        self._native = _native.fit_hermite(xs, ys2, method, None)
        self.context = context


class BSplines(_Batch):
    """Many `BSpline`s of one degree k <= 3 in one batch: `ts` a list of knot arrays (or a 2-D
    array, one row per spline), `cs` matching (n_i, m) arrays of real coefficients (or an
    (S, n, m) array; rows past n_i are ignored, as BSpline's); each spline's pieces are made
    once, all splines' together. `extrapolate` (True, False or "periodic") is the default of
    `integrate` (False: zero outside each base interval, as BSpline's), `roots` and `solve`;
    calls take x within each spline's base interval (see `_Batch`). `batch[i]` is spline i as
    a `BSpline`."""

    k: int
    # The lams a smoothing batch used (make_smoothing_splines), (S,) + y's trailing shape.
    lam: np.ndarray
    # Where the splines' t and c come from: ("given", ts, cs, trailing shape), or ("fitted",
    # the knots, bc_type, trailing shape) for make_interp_splines.
    _source: tuple
    _zero_outside = True

    def __init__(self, ts, cs, k: int = 3, extrapolate=True, context: Context | None = None):
        k = _natural("k", k)
        if k > 3:
            raise ValueError(f"k: a batch evaluates degrees up to 3, got {k} (BSpline takes "
                             f"any)")
        # As the extension takes them (a 2-D ts or 3-D cs stays one array, borrowed once), and
        # as lists of the splines' arrays.
        ts_given, cs_given, trailing = self._inputs(ts, cs, "cs", "ts")
        ts, cs2 = list(ts_given), list(cs_given)
        if len(ts) != len(cs2):
            raise ValueError(f"cs: {len(cs2)} splines' coefficients for {len(ts)} knot arrays")

        def named(s, what):
            return f"{what}s[{s}]"

        _bspl.check_many(ts, [len(c) for c in cs2], k, named)
        for i, c in enumerate(cs2):
            if not np.all(np.isfinite(c)):
                raise ValueError(f"cs[{i}]: the coefficients must be finite")
        self._build(ts_given, cs_given, ts, cs2, k, trailing, extrapolate, context)

    def _build(self, ts_given, cs_given, ts, cs2, k, trailing, extrapolate, context) -> None:
        """The pieces of checked splines: `ts_given`/`cs_given` as the extension takes them (a
        2-D / 3-D array, or lists), `ts`/`cs2` as lists of each spline's arrays."""
        if k > 3:
            raise ValueError(f"k: a batch's splines are evaluated up to degree 3, got {k} "
                             f"(make_splrep and BSpline take degree {k} one spline at a time)")
        self._native = piece_tables([], [], "cs") if not ts else None
        if k == 3 and ts:
            # The crate's cubic B-splines (kind "nurbs"), made on every thread; None for what
            # it does not take but SciPy does (a knot inside the base interval 4 times, where
            # the spline breaks), whose pieces come from NumPy below.
            self._native = _native.fit_bspline(ts_given, cs_given)
        if self._native is None:
            made = _bspl.many_pieces(ts, cs2, k)
            # Each spline's extent: the largest per-column spread of its coefficients.
            n = [len(t) - k - 1 for t in ts]
            used = np.concatenate([c[:count] for c, count in zip(cs2, n)])
            starts = np.concatenate([[0], np.cumsum(n)[:-1]])
            spread = np.maximum.reduceat(used, starts, axis=0) - np.minimum.reduceat(
                used, starts, axis=0)
            self._native = piece_tables(made, spread.max(axis=1), "cs")
        self.k, self.context = k, context
        extrapolate = _extrapolate(extrapolate)
        self._extrapolates = True if extrapolate is None else extrapolate
        self._source = ("given", ts, cs2, trailing)

    def __getitem__(self, i: int) -> BSpline:
        i = range(len(self))[i]
        how, first, second, trailing = self._source
        if how == "given":
            t, c = np.array(first[i]), second[i]
        else:
            t, c = interp_coefficients(first[i], self._native.coefficients(i), second)
        c = c.reshape((len(c), *trailing))
        return BSpline.construct_fast(t, np.array(c), self.k, self._extrapolates, 0,
                                      self.context)


def make_interp_splines(xs, ys, bc_type=None, context: Context | None = None) -> BSplines:
    """Many `make_interp_spline(x, y, k=3, bc_type=bc_type)`s in one batch: `xs` and `ys` as
    `CubicSplines` takes them, fitted together; evaluated as their fitted pieces, `batch[i]`
    is spline i with SciPy's knots and coefficients."""
    bc = interp_bc(bc_type)
    batch = BSplines.__new__(BSplines)
    # A 2-D xs stays one array: the extension borrows it once (not once per row).
    xs, ys2, trailing = batch._inputs(xs, ys)
    if bc == "not-a-knot":
        for i, x in enumerate(xs):
            if len(x) < 4:
                raise ValueError(f"xs[{i}]: not-a-knot needs at least 4 points for k=3, got "
                                 f"{len(x)}")
    name, start, end = bc_of(bc, trailing, broadcast=True)
    batch._native = _native.fit(xs, ys2, name, start, end)
    batch.k, batch.context = 3, context
    batch._extrapolates = "periodic" if bc == "periodic" else True
    batch._source = ("fitted", [np.array(x) for x in xs], bc, trailing)
    return batch


def _fitted_batch(xs, ys, fit, context) -> BSplines:
    """A BSplines batch of cubic-or-lower fits: `fit(xs, ys2, m)` gives each series' knots,
    (rows, m) coefficients and degree from the checked arrays (valid splines, not checked
    again; their arrays stacked for the extension where they share a shape)."""
    batch = BSplines.__new__(BSplines)
    xs, ys2, trailing = batch._inputs(xs, ys)
    m = int(np.prod(trailing, dtype=np.int64))
    ts, cs, k = fit(xs if isinstance(xs, np.ndarray) else list(xs), ys2, m)
    cs_given: Any
    ts_given: Any
    if isinstance(ts, _Laid) and isinstance(cs, _Laid):
        # Laid end to end by the fit: handed over as they are, the lists their views.
        batch._build((ts.flat, ts.offsets), (cs.flat, cs.offsets), ts.parts(), cs.parts(), k,
                     trailing, True, context)
        return batch
    if isinstance(cs, np.ndarray):
        # Every spline's coefficients in one (S, n, m) array.
        cs_given = _aligned(cs, "cs")
        cs = list(cs_given)
    else:
        cs = [np.ascontiguousarray(c).reshape(len(c), m) for c in cs]
        cs_given = None
    if isinstance(ts, np.ndarray):
        # One knot vector for all, a row each.
        even, ts_given = True, _aligned(ts, "ts")
    else:
        even = len({len(t) for t in ts}) == 1
        # Ragged knots and coefficients go laid end to end with their offsets (two borrows).
        ts_given = _aligned(np.stack(ts), "ts") if ts and even else _end_to_end(ts, "ts")
    if cs_given is None:
        cs_given = _aligned(np.stack(cs), "cs") if cs and even else _end_to_end(cs, "cs")
    batch._build(ts_given, cs_given, list(ts), cs, k, trailing, True, context)
    return batch


def make_smoothing_splines(xs, ys, ws=None, lams=None,
                           context: Context | None = None) -> BSplines:
    """Many `make_smoothing_spline(x, y, w, lam)`s in one call, each series its own x (a list
    of 1-D arrays or a 2-D array), y ((n_i,) or (n_i, m): each column its own lam), weights
    (`ws`, None for ones) and lam (`lams`: None for GCV, one number for all, or one per series
    (S,) or per series and column (S, m)), fitted on every thread. The batch's `lam` holds the
    lams used, (S,) + y's trailing shape; `batch[i]` is series i's spline with SciPy's knots
    and coefficients."""
    chosen = []

    def fit(xs, ys2, m):
        ts, cs, lam = _smoothing.fit_many(xs, ys2, ws, lams, m)
        chosen.append(lam)
        return ts, cs, 3

    batch = _fitted_batch(xs, ys, fit, context)
    trailing = batch._source[3]
    batch.lam = chosen[0].reshape((len(chosen[0]), *trailing))
    return batch


def make_lsq_splines(xs, ys, ts, k: int = 3, ws=None, context: Context | None = None) -> BSplines:
    """Many `make_lsq_spline(x, y, t, k, w)`s in one call, each series its own x (a list of
    1-D arrays or a 2-D array), y ((n_i,) or (n_i, m)) and weights (`ws`, None for ones), on
    one knot vector `ts` for all or one per series, degree k <= 3, fitted on every thread.
    `batch[i]` is series i's spline."""
    return _fitted_batch(xs, ys, lambda xs, ys2, m: (*_lsq.fit_many(xs, ys2, ts, k, ws), k),
                         context)


def make_splreps(xs, ys, ws=None, s=None, k: int = 3, xb=None, xe=None, nest=None,
                 bc_type=None, context: Context | None = None) -> BSplines:
    """Many `make_splrep(x, y, w=w, s=s, k=k, xb=xb, xe=xe, nest=nest, bc_type=bc_type)`s in
    one call, each series its own x (a list of 1-D arrays or a 2-D array), y, weights (`ws`,
    None for ones) and s (one value > 0 for all, or one per series), degree k <= 3,
    FITPACK's knots found for each on every thread. `xb`/`xe`: None (each series' first and
    last x), or one value or one per series. bc_type "periodic": every series periodic (its
    first and last y equal). `batch[i]` is series i's spline, SciPy's knots and
    coefficients."""
    periodic = _fitpack_repro.periodic_bc(bc_type)
    if s is None:
        raise ValueError("s: give the smoothing (> 0) of every series; s = 0 interpolates: "
                         "make_interp_splines")
    ends = None if xb is None and xe is None else (xb, xe)

    def fit(xs, ys2, m):
        if m != 1:
            raise ValueError(f"ys: one value per x (make_splpreps fits curves), got {m}")
        if ends is not None and (ends[0] is None or ends[1] is None):
            raise ValueError("xb, xe: give both or neither")
        ts, cs, _ = _fitpack_repro.fit_many(xs, ys2, ws, s, k, ends, nest, periodic)
        return ts, [c[:, 0] for c in cs], k

    return _fitted_batch(xs, ys, fit, context)


def make_splpreps(points, ws=None, us=None, s=None, k: int = 3, nest=None, bc_type=None,
                  context: Context | None = None):
    """Many `make_splprep(x, w=w, u=u, s=s, k=k, nest=nest, bc_type=bc_type)`s in one call:
    `points` a list of (d, m_i) coordinate arrays (each as make_splprep's x) or one (S, d, m)
    array, `us` their parameters (None: each curve's normalised chord lengths), `s` one value
    > 0 for all or one per curve, degree k <= 3, fitted on every thread; bc_type "periodic"
    for closed curves (each one's last point its first). Returns (batch, us): the batch's
    curves evaluate to (N, d) rows (`batch[i]` has c of shape (n_i, d), axis 0, where
    make_splprep's BSpline has axis 1: `batch[i](u).T` is its value)."""
    periodic = _fitpack_repro.periodic_bc(bc_type)
    if s is None:
        raise ValueError("s: give the smoothing (> 0) of every curve; s = 0 interpolates: "
                         "make_interp_splines")
    rows: Any
    points = _stacked(points, points)
    if isinstance(points, np.ndarray) and points.ndim == 3:
        # Curves of one shape: one (S, m, d) array, their chord lengths all at once.
        rows = np.ascontiguousarray(np.swapaxes(_float64(points, "points"), 1, 2))
        if us is None:
            steps = np.sqrt(np.sum(np.diff(rows, axis=1) ** 2, axis=2))
            lengths = np.cumsum(steps, axis=1)
            us = np.concatenate([np.zeros((len(rows), 1)), lengths / lengths[:, -1:]], axis=1)
    else:
        rows = [np.ascontiguousarray(_float64(p, f"points[{i}]").T)
                for i, p in enumerate(points)]
    for i, r in enumerate(rows):
        if r.ndim != 2 or len(r) <= operator.index(k):
            raise ValueError(f"points[{i}]: needs more points than the degree k = {k}, got "
                             f"shape {np.shape(r)[::-1]}")
    if us is None and not isinstance(rows, np.ndarray):
        us = [_fitpack_repro.chord_lengths(r) for r in rows]
    if isinstance(us, np.ndarray) and us.ndim == 2:
        us = _aligned(us, "us")
    else:
        us = [np.ascontiguousarray(_float64(u, f"us[{i}]")) for i, u in enumerate(us)]

    def fit(xs, ys2, m):
        ts, cs, _ = _fitpack_repro.fit_many(xs, ys2, ws, s, k, None, nest, periodic)
        return ts, cs, k

    return _fitted_batch(us, rows, fit, context), list(us)


class PPolys(_Batch):
    """Many `PPoly`s of degree <= 3 in one batch: `cs` a list of (k, P_i) or (k, P_i, m)
    coefficient arrays in SciPy's layout (k <= 4, one k and m for all), `xs` their P_i + 1
    increasing breakpoints each. `extrapolate` (True, False or "periodic") is the default of
    `integrate`, `roots` and `solve`; calls take x within each spline's breakpoints (see
    `_Batch`)."""

    def __init__(self, cs, xs, extrapolate=None, context: Context | None = None):
        cs = [np.asarray(_float64(c, f"cs[{i}]")) for i, c in enumerate(cs)]
        xs = [_flat(x, f"xs[{i}]") for i, x in enumerate(xs)]
        if len(cs) != len(xs):
            raise ValueError(f"cs: {len(cs)} coefficient arrays for {len(xs)} breakpoint arrays")
        shape = cs[0].shape[:1] + cs[0].shape[2:] if cs else (4,)
        pieces = []
        for i, (c, x) in enumerate(zip(cs, xs)):
            if c.ndim not in (2, 3) or c.shape[:1] + c.shape[2:] != shape or shape[0] > 4:
                raise ValueError(f"cs[{i}]: must have the shape (k, P, ...) of cs[0], {shape} "
                                 f"with k <= 4 (degree 3 at most), got {c.shape}")
            if len(x) != c.shape[1] + 1 or not np.all(np.diff(x) > 0):
                raise ValueError(f"xs[{i}]: must be {c.shape[1] + 1} increasing breakpoints "
                                 f"for {c.shape[1]} pieces, got {len(x)}")
            pieces.append((x, c.reshape(c.shape[0], c.shape[1], -1)))
        # Each spline's extent: the spread of its values at the pieces' starts.
        extents = [float(np.max(np.ptp(c[-1], axis=0))) for _, c in pieces]
        self._native = piece_tables(pieces, extents, "cs")
        self.context = context
        extrapolate = _extrapolate(extrapolate)
        self._extrapolates = True if extrapolate is None else extrapolate


def _evaluate(splines: list, points: list, nu, extrapolate) -> tuple:
    """Each tensor spline at its points (N_i, d_i) in one native call: (values (N, m),
    offsets); NdBSpline's rules for nu and complex coefficients (the same dtype for all)."""
    orders = [derivative_orders(nu, len(s.t)) for s in splines]
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
