"""Smoothing splines with FITPACK's knot placement (SciPy's `make_splrep` and `make_splprep`),
one or a batch: SciPy's checks and messages here, the fit in the extension
(`python/src/fitpack.rs`, and `periodic.rs` for bc_type "periodic": the knot search, the
discontinuity rows and the rational root finder of Dierckx's curfit and percur, step for
step as SciPy's `_fitpack_repro`), every series on its own thread."""

from __future__ import annotations

import operator
import warnings

import numpy as np

from . import _native
from ._bsplines import BSpline, make_interp_spline
from ._context import Context
from ._helpers import _aligned, _batch, _float64, _xs_and_weights

# SciPy's warnings when the root finder stops short of fp = s (its ier 2 and 3).
_STOPPED = {
    2: "error. a theoretically impossible result was found during the iteration process for "
       "finding a smoothing spline with fp = s. probably causes : s too small. there is an "
       "approximation returned but the corresponding weighted sum of squared residuals does "
       "not satisfy the condition abs(fp-s)/s < tol.",
    3: "error. the maximal number of iterations maxit (set to 20 by the program) allowed for "
       "finding a smoothing spline with fp=s has been reached. probably causes : s too small "
       "there is an approximation returned but the corresponding weighted sum of squared "
       "residuals does not satisfy the condition abs(fp-s)/s < tol.",
}


def periodic_bc(bc_type) -> bool:
    """Whether bc_type asks for a periodic fit (SciPy's `_validate_bc_type`)."""
    if bc_type is None or (isinstance(bc_type, str) and bc_type == "not-a-knot"):
        return False
    if isinstance(bc_type, str) and bc_type == "periodic":
        return True
    raise ValueError(f"bc_type: Only 'not-a-knot' and 'periodic' boundary conditions are "
                     f"recognised, found {bc_type}")


def fpcheck(x: np.ndarray, t: np.ndarray, k: int, periodic: bool = False) -> None:
    """FITPACK's checks of given knots t against x (fpchec, or fpchep for a periodic fit),
    in SciPy's words."""
    if x.ndim != 1 or t.ndim != 1:
        raise ValueError(f"Expect `x` and `t` be 1D sequences. Got x = {x} and t = {t}")
    m, n = len(x), len(t)
    nk1 = n - k - 1
    if periodic and not k + 1 <= nk1 <= m + k - 1:
        raise ValueError(f"Need k+1 <= n-k-1 <= m+k-1. Got m = {m}, n = {n}, k = {k}")
    if not periodic and not k + 1 <= nk1 <= m:
        raise ValueError(f"Need k+1 <= n-k-1 <= m. Got m = {m}, n = {n} and k = {k}.")
    if np.any(t[:k + 1] > t[1:k + 2]):
        raise ValueError(f"First k knots must be ordered; got t = {t}.")
    if np.any(t[nk1:] < t[nk1 - 1:-1]):
        raise ValueError(f"Last k knots must be ordered; got t = {t}.")
    if np.any(t[k + 1:n - k] <= t[k:n - k - 1]):
        raise ValueError(f"Internal knots must be distinct. Got t = {t}.")
    if x[0] < t[k] or x[-1] > t[n - k - 1]:
        raise ValueError(f"Out of bounds: x = {x} and t = {t}.")
    message = f"Schoenberg-Whitney condition is violated with t = {t} and x = {x}."
    if periodic:
        if not _periodic_schoenberg_whitney(x, t, k):
            raise ValueError(message)
        return
    if x[0] >= t[k + 1] or x[-1] <= t[n - k - 2]:
        raise ValueError(message)
    # Each inner B-spline j (1 <= j <= n - k - 3) needs a data point strictly inside
    # (t_j, t_{j+k+1}), later than the one the previous took.
    for j in range(1, n - k - 2):
        i = int(np.argmax(x > t[j]))
        if i >= m - 1 or x[i] >= t[j + k + 1]:
            raise ValueError(message)


def _periodic_schoenberg_whitney(x: np.ndarray, t: np.ndarray, k: int) -> bool:
    """fpchep's condition: for some cyclic shift of the data (the points before the shift
    moved a period on), every B-spline j = k .. n-k-2 holds a point strictly inside its
    support (t_j, t_{j+k+1})."""
    n = len(t)
    per = t[n - k - 1] - t[k]
    lower, upper = t[k:n - k - 1], t[2 * k + 1:n]
    for shift in range(1, len(x)):
        points = np.sort(np.concatenate([x[shift:], x[:shift] + per]))
        inside = (np.searchsorted(points, upper, "left")
                  - np.searchsorted(points, lower, "right"))
        if np.all(inside > 0):
            return True
    return False


def _validated(x, y, w, k, s, xb, xe, parametric: bool, periodic: bool = False):
    """SciPy's `_validate_inputs`: float64 arrays (y 2-D), the weights, k, s and [xb, xe]."""
    x = np.ascontiguousarray(_float64(x, "x"))
    y = np.ascontiguousarray(_float64(y, "y"))
    if w is None:
        w = np.ones_like(x)
    else:
        w = np.ascontiguousarray(_float64(w, "w"))
        if w.ndim != 1:
            raise ValueError(f"w.ndim = {w.ndim} not implemented yet.")
        if (w < 0).any():
            raise ValueError("Weights must be non-negative")
        if w.sum() == 0:
            raise ValueError("All weights are zero.")
    if y.ndim == 0 or y.ndim > 2:
        raise ValueError(f"y.ndim = {y.ndim} not supported (must be 1 or 2.)")
    if parametric and y.ndim != 2:
        raise ValueError(f"y.ndim = {y.ndim} != 2 not supported with parametric = True.")
    if not parametric:
        if y.ndim != 1:
            raise ValueError(f"y.ndim = {y.ndim} != 1 not supported with parametric = False.")
        y = y[:, None]
    if w.shape[0] != x.shape[0]:
        raise ValueError(f"Weights is incompatible: w.shape ={w.shape} != {x.shape}.")
    if x.shape[0] != y.shape[0]:
        raise ValueError(f"Data is incompatible: x.shape = {x.shape} and y.shape = {y.shape}.")
    if x.ndim != 1 or (x[1:] < x[:-1]).any():
        raise ValueError("Expect `x` to be an ordered 1D sequence.")
    k = operator.index(k)
    if not 1 <= k <= 6:
        raise ValueError(f"k: degrees 1 to 6 are fitted here, got {k}")
    if not np.isfinite(s) or s < 0:
        raise ValueError(f"`s` must be non-negative. Got s = {s}")
    xb = float(np.min(x)) if xb is None else float(xb)
    xe = float(np.max(x)) if xe is None else float(xe)
    if periodic and not np.allclose(y[0], y[-1], atol=1e-15):
        raise ValueError("First and last points does not match which is required for "
                         "`bc_type='periodic'`.")
    return x, y, w, k, float(s), xb, xe


def _fit(x, y, w, xb, xe, k, s, t, nest, periodic: bool):
    """One FITPACK fit in the extension: (t, c (rows, d))."""
    m = len(x)
    if nest is not None:
        nest = operator.index(nest)
        if nest < 2 * (k + 1):
            raise ValueError(f"`nest` too small: nest = {nest} < 2*(k+1) = {2 * (k + 1)}.")
        if t is not None:
            raise ValueError("Either supply `t` or `nest`.")
    knots = None
    if t is not None:
        t = np.ascontiguousarray(_float64(t, "t"))
        fpcheck(x, t, k, periodic)
        knots = (_aligned(t, "t"), np.array([0, len(t)], np.int64))
    if periodic and m < 2:
        raise ValueError(f"x: a periodic fit needs m >= 2 points, got {m}")
    if not periodic and m <= k:
        raise ValueError(f"x: m > k must hold, got m = {m} points for k = {k}")
    made, offsets, c, iers = _native.fit_splrep([_aligned(x, "x")], [_aligned(y, "y")],
                                                [_aligned(w, "w")], [xb], [xe], k, [s], knots,
                                                nest, periodic)
    _warn(iers)
    return np.array(made[offsets[0]:offsets[1]]), c


def _warn(iers) -> None:
    for ier in set(iers) - {0}:
        warnings.warn(RuntimeWarning(_STOPPED[ier]), stacklevel=4)


def make_splrep(x, y, *, w=None, xb=None, xe=None, k: int = 3, s: float = 0, t=None,
                nest=None, bc_type=None, context: Context | None = None) -> BSpline:
    """`scipy.interpolate.make_splrep(x, y, w=None, xb=None, xe=None, k=3, s=0, t=None,
    nest=None, bc_type=None)`: the spline with fp = sum (w_i (y_i - f(x_i)))^2 <= s and
    FITPACK's knots (the same knots and coefficients as SciPy's for the same s), or the
    interpolating spline for s = 0. bc_type "periodic": the periodic spline of period
    xe - xb (y's first and last values must match; the last point is not fitted)."""
    if s == 0:
        if t is not None or w is not None or nest is not None:
            raise ValueError("s==0 is for interpolation only")
        return make_interp_spline(x, y, k=k, bc_type=bc_type, context=context)
    periodic = periodic_bc(bc_type)
    x, y, w, k, s, xb, xe = _validated(x, y, w, k, s, xb, xe, False, periodic)
    knots, c = _fit(x, y, w, xb, xe, k, s, t, nest, periodic)
    return BSpline.construct_fast(knots, np.ascontiguousarray(c[:, 0]), k, context=context)


def chord_lengths(points: np.ndarray) -> np.ndarray:
    """SciPy's default parameter of a point sequence (m, d): cumulative distances, 0 to 1."""
    steps = np.sqrt(np.sum((points[1:] - points[:-1]) ** 2, axis=1))
    u = np.cumsum(steps)
    return np.concatenate([[0.0], u / u[-1]])


def make_splprep(x, *, w=None, u=None, ub=None, ue=None, k: int = 3, s: float = 0, t=None,
                 nest=None, bc_type=None, context: Context | None = None):
    """`scipy.interpolate.make_splprep(x, w=None, u=None, ub=None, ue=None, k=3, s=0, t=None,
    nest=None, bc_type=None)`: the parametric curve through (or, for s > 0, near) the points
    x (a list of d coordinate arrays, or a (d, m) array), as (BSpline with axis=1, u), u by
    default the normalised chord lengths. SciPy's knots and coefficients for the same s."""
    points = np.stack([_float64(v, "x") for v in x], axis=1)
    if points.ndim != 2:
        raise ValueError(f"x: a list of coordinate arrays (or a (d, m) array), got "
                         f"{np.ndim(x)} dimensions")
    if points.shape[0] <= operator.index(k):
        raise ValueError(f"x: needs more points than the degree k = {k}, got "
                         f"{points.shape[0]}")
    if u is None:
        u = chord_lengths(points)
    periodic = periodic_bc(bc_type)
    if s == 0:
        # SciPy's: the interpolating curve, not-a-knot even for bc_type "periodic".
        if t is not None or w is not None or nest is not None:
            raise ValueError("s==0 is for interpolation only")
        return make_interp_spline(u, points.T, k=k, axis=1, context=context), u
    u, points, w, k, s, ub, ue = _validated(u, points, w, k, s, ub, ue, True, periodic)
    knots, c = _fit(u, points, w, ub, ue, k, s, t, nest, periodic)
    return BSpline(knots, np.ascontiguousarray(c.T), k, axis=1, context=context), u


def fit_many(us: list, points, ws, s, k: int, ends, nest, periodic: bool = False) -> tuple:
    """Many FITPACK fits (`us` checked 1-D arrays, `points` their (m_i, d) arrays or one
    (S, m, d) array): their knots, coefficients ((n_i, d) each) and the root finders' iers.
    `s` one value or one per series; `ends` (xb, xe) arrays or None (each series' own);
    `periodic` for percur's periodic fits."""
    count = len(us)
    k = operator.index(k)
    s = _float64(s, "s")
    if s.ndim > 1 or (s.ndim == 1 and len(s) != count):
        raise ValueError(f"s: one value, or one per series ({count}), got shape {s.shape}")
    s = np.broadcast_to(s, (count,)).astype(np.float64)
    if np.any(~(s > 0)) or not np.all(np.isfinite(s)):
        raise ValueError("s: every series' s must be > 0 and finite (s = 0 interpolates: "
                         "make_interp_splines)")
    if not 1 <= k <= 6:
        raise ValueError(f"k: degrees 1 to 6 are fitted here, got {k}")
    if nest is not None and operator.index(nest) < 2 * (k + 1):
        raise ValueError(f"`nest` too small: nest = {nest} < 2*(k+1) = {2 * (k + 1)}.")
    if ends is None:
        # Each series' first and last u (an empty series is refused in the extension); a 2-D
        # us' columns, not its rows one by one.
        if isinstance(us, np.ndarray) and us.shape[1]:
            xb, xe = us[:, 0].tolist(), us[:, -1].tolist()
        else:
            xb = [float(u[0]) if len(u) else 0.0 for u in us]
            xe = [float(u[-1]) if len(u) else 0.0 for u in us]
    else:
        xb, xe = ([float(v) for v in np.broadcast_to(_float64(e, "ends"), (count,))]
                  for e in ends)
    if not count:
        return [], [], []
    us, ws, _ = _xs_and_weights(us, ws, "us")
    knots, offsets, c, iers = _native.fit_splrep(us, _batch(points, "points", 2), ws, xb, xe, k,
                                                 list(s), None, nest, periodic)
    _warn(iers)
    ts = [knots[offsets[i]:offsets[i + 1]] for i in range(count)]
    ends_c = np.cumsum([len(t) - k - 1 for t in ts])
    return ts, np.split(c, ends_c[:-1]), iers
