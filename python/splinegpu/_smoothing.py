"""Cubic smoothing splines (SciPy's `make_smoothing_spline`), one or a batch: the checks and
the shapes here, the fit in the extension (`python/src/smoothing.rs`: SciPy's banded O(n)
system, GCV's lam by SciPy's bounded search), four series side by side in vector lanes on
every thread."""

from __future__ import annotations

from typing import Any

import numpy as np

from . import _native
from ._bsplines import BSpline
from ._context import Context
from ._helpers import _aligned, _axis, _batch, _float64, _Laid, _xs_and_weights


def knots(x: np.ndarray) -> np.ndarray:
    """The smoothing spline's knots: every x, each end three more times."""
    return np.concatenate([np.repeat(x[:1], 3), x, np.repeat(x[-1:], 3)])


def check_series(x: np.ndarray, w: np.ndarray) -> None:
    """SciPy's checks of one series' x and w, in its order and words."""
    # make_smoothing_spline checks ascending x first, where SciPy does; NaN is caught here.
    if not np.all(np.isfinite(x)):
        raise ValueError("``x`` should be an ascending array")
    if w.shape != x.shape:
        raise ValueError(f"w: one weight per x ({x.shape}), got shape {w.shape}")
    if np.any(~(w > 0)) or not np.all(np.isfinite(w)):
        raise ValueError("Invalid vector of weights")
    if x.shape[0] <= 4:
        raise ValueError("``x`` and ``y`` length must be at least 5")


def lam_of(lam, shape: tuple, name: str = "lam") -> np.ndarray:
    """lam as one value per column (NaN: chosen by GCV), refused when negative."""
    if lam is None:
        return np.full(shape, np.nan)
    given = _float64(lam, name)
    if np.any(given < 0) or np.any(np.isnan(given)):
        raise ValueError("Regularization parameter should be non-negative")
    try:
        return np.array(np.broadcast_to(given, shape))
    except ValueError:
        raise ValueError(f"{name}: one value, or one per column {shape}, got shape "
                         f"{given.shape}") from None


def make_smoothing_spline(x, y, w=None, lam=None, *, axis: int = 0,
                          context: Context | None = None) -> BSpline:
    """`scipy.interpolate.make_smoothing_spline(x, y, w=None, lam=None, axis=0)`: the cubic
    minimising sum w_i (y_i - f(x_i))^2 + lam * integral f''^2, lam chosen by generalised
    cross-validation where None (SciPy's criterion and search, each column of y its own lam).
    The lam used is the result's `lam` (a number, or an array of y's trailing shape). A
    complex y is refused (SciPy drops its imaginary part)."""
    x = np.array(_float64(x, "x"), order="C")
    y = _float64(y, "y")
    if y.ndim == 0:
        raise ValueError("y: must be at least 1-D, got a 0-d array")
    axis = _axis(axis, y.ndim, "y")
    if x.ndim == 1 and np.any(x[1:] - x[:-1] <= 0):
        raise ValueError("``x`` should be an ascending array")
    if x.ndim != 1 or x.shape[0] != y.shape[axis]:
        raise ValueError(f"``x`` should be 1D and x.shape = {x.shape} == y.shape = {y.shape}")
    w = np.ones(len(x)) if w is None else _float64(w, "w")
    check_series(x, w)
    y = np.moveaxis(y, axis, 0)
    if not np.all(np.isfinite(y)):
        raise ValueError("y: must be finite (NaN or infinity found)")
    trailing = y.shape[1:]
    columns = y.reshape(len(x), -1)
    lams = lam_of(lam, (1, *trailing)).reshape(1, -1)
    if columns.shape[1] == 0:
        c, used = np.zeros((len(x) + 2, 0)), lams
    else:
        _, c, used = _native.fit_smoothing([_aligned(x, "x")], [_aligned(columns, "y")],
                                           [_aligned(w, "w")], _aligned(lams, "lam"))
    c = c.reshape((len(x) + 2, *trailing))
    spline = BSpline.construct_fast(knots(x), np.ascontiguousarray(c), 3, axis=axis,
                                    context=context)
    spline.lam = float(used[0, 0]) if trailing == () else used[0].reshape(trailing)
    return spline


def fit_many(xs: list, ys: Any, ws, lams, columns: int) -> tuple:
    """Many series' smoothing splines (`xs` checked 1-D arrays, `ys` their (n_i, m) arrays or
    one (S, n, m) array): their knots and coefficients laid end to end (`_Laid`: knots
    (sum n_i + 6), coefficients (sum n_i + 2, m)) and lams (S, m)."""
    count = len(xs)
    xs, ws, offsets = _xs_and_weights(xs, ws)
    # Each series' x, y and w are checked in the extension, in `check_series`' words.
    given = _float64(lams, "lams") if lams is not None else None
    if given is not None and given.ndim == 1:
        given = given[:, None]
    lam = lam_of(given, (count, columns), "lams")
    if count == 0:
        return [], [], lam
    t, c, used = _native.fit_smoothing(xs, _batch(ys, "ys", 2), ws, _aligned(lam, "lams"))
    series = np.arange(count + 1, dtype=np.int64)
    return _Laid(t, offsets + 6 * series), _Laid(c, offsets + 2 * series), used
