"""Least-squares splines (SciPy's `make_lsq_spline`), one or a batch: the checks and shapes
here, the fit in the extension (`python/src/lsq.rs`: Givens rotations into a banded
triangle, O(m k^2)), every series on its own thread."""

from __future__ import annotations

import operator

import numpy as np

from . import _native
from ._bsplines import BSpline
from ._context import Context
from ._helpers import _aligned, _axis, _batch, _end_to_end, _float64, _xs_and_weights


def _numbers(a, name: str) -> np.ndarray:
    """`a` as float64 (complex128 if complex). Finiteness is checked in the extension's one
    pass over the data, whatever `check_finite` says (NaN would only make NaN coefficients)."""
    a = np.asarray(a)
    if a.dtype.kind not in "biufc":
        raise TypeError(f"{name}: must be numbers, got an array of {a.dtype}")
    return a.astype(np.complex128 if a.dtype.kind == "c" else np.float64, copy=False)


def check(x: np.ndarray, y_rows: int, t: np.ndarray, k: int, w: np.ndarray,
          strict: bool) -> None:
    """SciPy's checks of a single fit that name what its messages name, in its order and
    words; the rest (x non-decreasing, every x inside the base interval, t sorted, w >= 0,
    finite values) the extension makes on the way in, naming them too (`_native_words`)."""
    if x.ndim != 1:
        raise ValueError("Expect x to be a 1-D sequence.")
    if x.shape[0] < k + 1:
        raise ValueError("Need more x points.")
    if k < 0:
        raise ValueError("Expect non-negative k.")
    if t.ndim != 1 or len(t) < 2 * k + 2:
        raise ValueError(f"Expect t to be a 1D strictly increasing sequence of at least "
                         f"{2 * k + 2} knots for degree {k}, got shape {t.shape}")
    if x.size != y_rows:
        raise ValueError(f"Shapes of x {x.shape} and y ({y_rows}, ...) are incompatible")
    if x.size != w.size:
        raise ValueError(f"w: Shapes of x {x.shape} and w {w.shape} are incompatible")
    if strict and np.any(x[1:] - x[:-1] <= 0):
        raise ValueError("Expect x to be a 1D strictly increasing sequence.")


def _native_words(error: ValueError) -> ValueError:
    """The extension's message of a batch of one, as a single call words it (no series
    index; w and y named as arguments)."""
    text = str(error)
    for batch, single in (("xs[0]: ", ""), ("ts[0]: ", ""), ("ws[0]: ", "w: "),
                          ("ys[0]: ", "y: ")):
        text = text.replace(batch, single)
    return ValueError(text)


def singular(i: int | None) -> ValueError:
    where = "" if i is None else f"series {i}: "
    return ValueError(f"{where}the least-squares matrix is singular: the knots and x violate "
                      f"the Schoenberg-Whitney conditions (a B-spline with no x inside its "
                      f"support)")


def make_lsq_spline(x, y, t, k: int = 3, w=None, axis: int = 0, check_finite: bool = True, *,
                    method: str = "qr", context: Context | None = None) -> BSpline:
    """`scipy.interpolate.make_lsq_spline(x, y, t, k=3, w=None, axis=0, check_finite=True,
    method="qr")`: the B-spline on knots t minimising sum (w_i (y_i - f(x_i)))^2, any k,
    complex y as its parts. Both methods solve by Givens rotations (the normal equations
    "norm-eq" would square the condition; it keeps its stricter check of x). Knots that no
    data supports (Schoenberg-Whitney) raise ValueError where SciPy's "qr" returns NaN, and
    `check_finite` is always on (NaN or infinity anywhere is refused, naming the argument)."""
    x = _numbers(x, "x")
    if np.iscomplexobj(x):
        raise ValueError("x: complex values are not supported")
    y = _numbers(y, "y")
    t = _numbers(t, "t")
    if np.iscomplexobj(t):
        raise ValueError("t: complex values are not supported")
    w = np.ones_like(x) if w is None else _float64(w, "w")
    k = operator.index(k)
    if y.ndim == 0:
        raise ValueError("y: must be at least 1-D, got a 0-d array")
    axis = _axis(axis, y.ndim, "y")
    if axis:
        y = np.moveaxis(y, axis, 0)
    if method not in ("qr", "norm-eq"):
        raise ValueError(f"Unknown method = {method!r}.")
    check(x, y.shape[0], t, k, w, method == "norm-eq")
    trailing = y.shape[1:]
    columns = y.reshape(len(x), -1)
    if np.iscomplexobj(columns):
        columns = columns.view(np.float64)
    nc = len(t) - k - 1
    if columns.shape[1] == 0:
        c = np.zeros((nc, 0))
    else:
        try:
            c, _, bad = _native.fit_lsq([_aligned(x, "x")], [_aligned(columns, "y")],
                                        [_aligned(w, "w")], _aligned(t, "t"),
                                        np.array([0, len(t)], np.int64), k)
        except ValueError as e:
            raise _native_words(e) from None
        if bad is not None:
            raise singular(None)
    if np.iscomplexobj(y):
        c = np.ascontiguousarray(c).view(np.complex128)
    c = np.ascontiguousarray(c.reshape((nc, *trailing)))
    return BSpline.construct_fast(np.array(t, order="C"), c, k, axis=axis, context=context)


def fit_many(xs: list, ys, ts, k: int, ws) -> tuple:
    """Many series' least-squares coefficients ((len(t_i) - k - 1, m) each), `xs` checked 1-D
    arrays, `ys` their (n_i, m) arrays or one (S, n, m) array, `ts` one knot vector for all or
    one per series."""
    k = operator.index(k)
    if not 0 <= k <= 3:
        raise ValueError(f"k: a batch evaluates degrees 0 to 3, got {k}")
    count = len(xs)
    if not isinstance(ts, (list, tuple)) and np.ndim(ts) == 1:
        # One knot vector for all: laid end to end once, not copied per series.
        t = np.ascontiguousarray(_float64(ts, "ts"))
        ts = [t] * count
        t_flat, t_offsets = np.tile(t, count), np.arange(count + 1, dtype=np.int64) * len(t)
    else:
        ts = [np.ascontiguousarray(_float64(t, f"ts[{i}]")) for i, t in enumerate(ts)]
        if len(ts) != count:
            raise ValueError(f"ts: {len(ts)} knot vectors for {count} series")
        t_flat, t_offsets = _end_to_end(ts, "ts") if ts else (np.zeros(0), np.zeros(1, np.int64))
    xs, ws, _ = _xs_and_weights(xs, ws)
    if count == 0:
        return [], []
    # Each series checked in the extension, as `check` does, naming it.
    c, _, bad = _native.fit_lsq(xs, _batch(ys, "ys", 2), ws, _aligned(t_flat, "ts"), t_offsets,
                                k)
    if bad is not None:
        raise singular(bad)
    rows = np.diff(t_offsets) - (k + 1)
    if np.all(rows == rows[0]):
        # One row count for all (one knot vector): the (S, n, m) array, not S pieces, and
        # the knots (S, len(t)).
        return t_flat.reshape(count, -1), c.reshape(count, int(rows[0]), c.shape[1])
    return ts, np.split(c, rows.cumsum()[:-1])
