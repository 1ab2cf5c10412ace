"""SciPy's FITPACK doors with tck tuples: `splrep`, `splprep`, `splev`, `splint`, `sproot`,
`splder` and `splantider`, answered by this package's B-splines (a tck is (t, c, k), c
padded with zeros to len(t), as SciPy's; a parametric one holds a list of coordinate
arrays). A BSpline given in place of a tck is answered with a BSpline, as SciPy does.

`per=1` fits periodic splines as FITPACK's percur and clocur do: the period x[-1] - x[0],
the last point standing for the first (its value is not fitted; splprep sets it to the
first). task=-1 fits least squares on given knots. Differences, refused by name: task=1
(FITPACK's continued search), and given knots with `per=1`, raise NotImplementedError.
Smoothing (s > 0) places knots as SciPy's `make_splrep` does, which is FITPACK's rule
re-derived; SciPy's Fortran curfit and percur can place some knots elsewhere for the same s
(both meet fp <= s)."""

from __future__ import annotations

import warnings

import numpy as np

from . import _bspl, _collocation
from ._bsplines import BSpline, make_interp_spline
from ._fitpack_repro import chord_lengths, fpcheck, make_splprep, make_splrep
from ._lsq import make_lsq_spline
from ._ppoly import PPoly


def _tck(tck, name: str):
    """(t, c, k) of a tck tuple or a BSpline (`name` the caller, for SciPy's refusal of a
    BSpline of several values per x); c as an array, the coefficients along its last axis."""
    if isinstance(tck, BSpline) or (hasattr(tck, "tck") and hasattr(tck, "axis")):
        if np.ndim(tck.c) > 1:
            raise ValueError(f"Calling {name}() with BSpline objects with c.ndim > 1 is not "
                             f"allowed. Use BSpline.__call__(x) instead.")
        return tck.t, np.asarray(tck.c, dtype=np.float64), tck.k
    t, c, k = tck
    return np.asarray(t, dtype=np.float64), np.asarray(c, dtype=np.float64), int(k)


def _each(c: np.ndarray, one):
    """one(c_1d) for a 1-D c; for an N-D c (the legacy layout: coefficients last), a nested
    list of the results over c's leading axes, as SciPy's map over them."""
    if c.ndim > 1:
        return [_each(row, one) for row in c]
    return one(c)


def _padded(t: np.ndarray, c: np.ndarray) -> np.ndarray:
    """c with zeros to len(t) along its first axis, as FITPACK lays it out."""
    return _bspl.padded(t, np.asarray(c))


def _check_finite_input(x, name: str) -> np.ndarray:
    x = np.asarray(x, dtype=np.float64)
    if not np.all(np.isfinite(x)):
        raise ValueError(f"{name}: must be finite (NaN or infinity found)")
    return x


def _default_s(m: int, w) -> float:
    """SciPy's default smoothing: m - sqrt(2 m) with weights, 0 (interpolation) without."""
    return m - np.sqrt(2 * m) if w is not None else 0.0


def splrep(x, y, w=None, xb=None, xe=None, k: int = 3, task: int = 0, s=None, t=None,
           full_output: int = 0, per: int = 0, quiet: int = 1):
    """`scipy.interpolate.splrep`: the tck of the interpolating (s = 0), smoothing (s > 0,
    FITPACK's knots as make_splrep places them) or least-squares (interior knots t) spline
    of (x, y). full_output adds (fp, ier, msg)."""
    if task == -1 and t is None:
        raise TypeError("Knots must be given for task=-1")
    if task not in (0, -1):
        raise NotImplementedError(f"task: only task=0 and task=-1 (given knots t) are "
                                  f"implemented, got {task}")
    x = _check_finite_input(x, "x")
    y = _check_finite_input(y, "y")
    if y.ndim != 1:
        raise ValueError(f"y: one value per x (a 1-D array), got shape {y.shape}")
    if len(x) <= k:
        raise TypeError(f"m > k must hold: {len(x)} points for k = {k}")
    if s is None:
        s = _default_s(len(x), w)
    if per:
        if t is not None:
            raise NotImplementedError("t: periodic splrep with given knots (per=1 and t) "
                                      "is not implemented here")
        # percur: the last point stands for the first (its y is not fitted).
        y = np.concatenate([y[:-1], y[:1]])
        columns = _periodic(x, y[:, None], w, k, s)
        spline = BSpline.construct_fast(columns.t, columns.c[:, 0], k)
        result = (spline.t, _padded(spline.t, spline.c), spline.k)
        if full_output:
            return result, _fp(x[:-1], y[:-1], w, spline), 0, ""
        return result
    if t is not None:
        xb = x[0] if xb is None else xb
        xe = x[-1] if xe is None else xe
        knots = np.concatenate([[xb] * (k + 1), np.asarray(t, dtype=np.float64),
                                [xe] * (k + 1)])
        try:
            fpcheck(x, knots, k)
        except ValueError as e:
            # FITPACK's curfit refuses such knots before it fits; SciPy raises TypeError.
            raise TypeError(f"t: {e}") from e
        spline = make_lsq_spline(x, y, knots, k, w=w)
    elif s == 0 and w is None and xb is None and xe is None:
        spline = make_interp_spline(x, y, k=k)
    else:
        spline = make_splrep(x, y, w=w, xb=xb, xe=xe, k=k, s=s)
    result = (spline.t, _padded(spline.t, spline.c), spline.k)
    if full_output:
        return result, _fp(x, y, w, spline), 0, ""
    return result


def _fp(x: np.ndarray, y: np.ndarray, w, spline: BSpline) -> float:
    """FITPACK's fp: sum (w_i (y_i - s(x_i)))^2 over the points given (w's first len(x))."""
    weights = np.ones_like(x) if w is None else np.asarray(w, dtype=np.float64)[:len(x)]
    return float(np.sum((weights * (y - spline(x))) ** 2))


def _periodic(x: np.ndarray, y: np.ndarray, w, k: int, s: float, nest=None) -> BSpline:
    """FITPACK's periodic fit of y ((m, d), y[-1] = y[0]) over x, period x[-1] - x[0]: the
    interpolating spline on the periodic knots for s = 0, the smoothing spline otherwise;
    c (n - k - 1, d)."""
    if s == 0:
        t = _collocation.periodic(x, k)
        if k == 1:
            # percur's k = 1: the coefficients are the values.
            return BSpline.construct_fast(t, y, 1)
        return make_interp_spline(x, y, k=k, bc_type="periodic")
    if y.shape[1] == 1:
        spline = make_splrep(x, y[:, 0], w=w, k=k, s=s, bc_type="periodic")
        return BSpline.construct_fast(spline.t, spline.c[:, None], k)
    spline, _ = make_splprep(list(y.T), w=w, u=x, k=k, s=s, nest=nest, bc_type="periodic")
    return BSpline.construct_fast(spline.t, np.asarray(spline.c), k)


def splprep(x, w=None, u=None, ub=None, ue=None, k: int = 3, task: int = 0, s=None, t=None,
            full_output: int = 0, nest=None, per: int = 0, quiet: int = 1):
    """`scipy.interpolate.splprep`: ([t, [c_1, ..., c_d], k], u) of the parametric spline
    through (s = 0) or near (s > 0) the points x (a list of d coordinate arrays); task=-1:
    the least-squares curve on the knots t (its inner knots; the ends are [ub, ue]), as
    FITPACK's parcur. t is ignored for task=0, as SciPy's."""
    if task not in (0, -1):
        raise NotImplementedError(f"task: only task=0 and task=-1 are implemented, got {task}")
    if task == -1:
        if t is None:
            raise TypeError("Knots must be given for task=-1")
        if len(np.atleast_1d(t)) < 2 * k + 2:
            raise TypeError("There must be at least 2*k+2 knots for task=-1")
        if per:
            raise NotImplementedError("per: periodic splprep with given knots (task=-1) is "
                                      "not implemented here")
    if np.iscomplexobj(x):
        # SciPy's parcur takes real data and refuses the cast (its splrep warns instead).
        raise TypeError("x: Cannot cast array data from dtype('complex128') to "
                        "dtype('float64') according to the rule 'safe'")
    x = np.array(x, dtype=np.float64)
    if x.ndim != 2:
        raise ValueError(f"too many values to unpack: x must be a list of coordinate arrays "
                         f"or a 2-D array, got {x.ndim} dimensions")
    if per:
        # clocur closes the curve: its last point is set to the first (on a copy).
        if not quiet and np.any(x[:, -1] != x[:, 0]):
            warnings.warn(RuntimeWarning(f"Setting x[:, {x.shape[1] - 1}] = x[:, 0]"),
                          stacklevel=2)
        x[:, -1] = x[:, 0]
    points = [_check_finite_input(v, "x") for v in x]
    m = len(points[0])
    if m <= k:
        raise TypeError(f"m > k must hold: {m} points for k = {k}")
    if s is None:
        # splprep smooths by default, with or without weights (splrep interpolates).
        s = m - np.sqrt(2 * m)
    if u is None:
        steps = np.sqrt(np.sum(np.diff(x, axis=1) ** 2, axis=0))
        if np.any(steps == 0) and np.sum(steps) > 0 and np.any(np.diff(np.cumsum(steps)) <= 0):
            raise ValueError("Invalid inputs: the chord lengths of x repeat (a point given "
                             "twice in a row)")
    elif np.any(np.diff(np.asarray(u, dtype=np.float64)) <= 0):
        raise ValueError("Invalid inputs: u must be strictly increasing")
    if task == -1:
        u = chord_lengths(x.T) if u is None else np.asarray(u, dtype=np.float64)
        inner = np.asarray(t, dtype=np.float64)[k + 1:len(t) - k - 1]
        knots = np.concatenate([[u[0] if ub is None else ub] * (k + 1), inner,
                                [u[-1] if ue is None else ue] * (k + 1)])
        spline = make_lsq_spline(u, x.T, knots, k, w=w)
    elif per:
        u = chord_lengths(x.T) if u is None else np.asarray(u, dtype=np.float64)
        spline = _periodic(u, x.T.copy(), w, k, s, nest)
    elif s == 0:
        spline, u = make_splprep(points, u=u, k=k, s=0)
    else:
        spline, u = make_splprep(points, w=w, u=u, ub=ub, ue=ue, k=k, s=s, nest=nest)
    # SciPy's parametric tck keeps each coordinate's n coefficients unpadded.
    tck = [spline.t, list(np.asarray(spline.c).T), spline.k]
    if full_output:
        return (tck, u), 0.0, 0, ""
    return tck, u


def splev(x, tck, der: int = 0, ext: int = 0):
    """`scipy.interpolate.splev`: the spline (or its der-th derivative) at x, x's shape; ext
    0 extrapolates, 1 gives 0 outside [t_k, t_n], 2 raises ValueError there, 3 the end value.
    An N-D c (a parametric tck's list) gives a list of arrays, one per leading index."""
    t, c, k = _tck(tck, "splev")
    if not 0 <= der <= k:
        raise ValueError(f"0<=der={der}<=k={k} must hold")
    if ext not in (0, 1, 2, 3):
        raise ValueError(f"ext = {ext} not in (0, 1, 2, 3) ")
    x = np.asarray(x, dtype=np.float64)
    n = len(t) - k - 1
    lo, hi = t[k], t[n]
    outside = (x < lo) | (x > hi)
    if ext == 2 and np.any(outside):
        raise ValueError("Found x value not in the domain")
    at = (np.clip(x, lo, hi) if ext == 3 else x).ravel()

    def one(coefficients):
        spline = BSpline.construct_fast(t, np.ascontiguousarray(coefficients[:n]), k)
        values = np.asarray(spline(at, nu=der)).reshape(x.shape)
        return np.where(outside, 0.0, values) if ext == 1 else values

    return _each(c, one)


def splint(a, b, tck, full_output: int = 0):
    """`scipy.interpolate.splint`: the integral from a to b of the spline, taken as zero
    outside its base interval [t_k, t_n] (a nested list for an N-D c)."""
    if isinstance(tck, BSpline) and np.ndim(tck.c) == 1:
        # SciPy hands a BSpline to its own integrate (a 0-d array).
        value = tck.integrate(a, b, extrapolate=False)
        return (value, np.zeros(len(tck.c))) if full_output else value
    t, c, k = _tck(tck, "splint")
    n = len(t) - k - 1

    def one(coefficients):
        spline = BSpline.construct_fast(t, np.ascontiguousarray(coefficients[:n]), k,
                                        extrapolate=False)
        return float(spline.integrate(a, b, extrapolate=False))

    value = _each(c, one)
    if full_output:
        return value, np.zeros(n)
    return value


def sproot(tck, mest: int = 10):
    """`scipy.interpolate.sproot`: the zeros of a cubic spline within [t_3, t_n] (a nested
    list for an N-D c)."""
    t, c, k = _tck(tck, "sproot")
    if k != 3:
        raise ValueError("sproot works only for cubic (k=3) splines")
    if len(t) < 8:
        raise TypeError(f"The number of knots {len(t)}>=8")
    n = len(t) - k - 1

    def one(coefficients):
        pieces = PPoly.from_spline((t, coefficients[:n], k), extrapolate=False)
        roots = np.asarray(pieces.roots(discontinuity=False, extrapolate=False))
        return np.unique(roots[np.isfinite(roots)])

    return _each(c, one)


def _derived(tck, nu: int, anti: bool):
    if isinstance(tck, BSpline) or (hasattr(tck, "tck") and hasattr(tck, "axis")):
        return tck.antiderivative(nu) if anti else tck.derivative(nu)
    t, c, k = _tck(tck, "splder")
    if not anti and not 0 <= nu <= k:
        raise ValueError(f"Order of derivative (n = {nu!r}) must be <= order of spline "
                         f"(k = {k!r})")
    n = len(t) - k - 1
    # Here the coefficients run along c's first axis (trailing axes are values), as SciPy's.
    spline = BSpline.construct_fast(t, np.ascontiguousarray(c[:n]), k)
    made = spline.antiderivative(nu) if anti else spline.derivative(nu)
    return made.t, _padded(made.t, made.c), made.k


def splder(tck, n: int = 1):
    """`scipy.interpolate.splder`: the tck (or BSpline) of the n-th derivative."""
    return _derived(tck, n, anti=False)


def splantider(tck, n: int = 1):
    """`scipy.interpolate.splantider`: the tck (or BSpline) of the n-th antiderivative."""
    return _derived(tck, n, anti=True)


def insert(x, tck, m: int = 1, per: int = 0):
    """`scipy.interpolate.insert`: the knot x inserted m times (Boehm's rule; per=1 as FITPACK's
    periodic insertion). A BSpline gives a BSpline (its values along any trailing axes); a tck
    tuple a tck tuple (c padded to len(t)), a parametric one's c a list of arrays."""
    if isinstance(tck, BSpline):
        if not per:
            return tck.insert_knot(x, m)
        t, c = _inserted(tck.t, np.asarray(tck.c), tck.k, x, m, True)
        return BSpline.construct_fast(t, c, tck.k, tck.extrapolate, tck.axis, tck.context)
    t, c, k = tck
    t, k = np.asarray(t, dtype=np.float64), int(k)
    if m <= 0:
        raise ValueError(f"`m` must be positive, got {m = }.")
    n = len(t) - k - 1
    new_t = _inserted(t, np.zeros(n), k, x, m, bool(per))[0]

    def one(row: np.ndarray) -> np.ndarray:
        return _padded(new_t, _inserted(t, row[:n], k, x, m, bool(per))[1])
    # A parametric tck's c (a list of arrays), or an N-D c in the legacy layout (coefficients
    # along its last axis): a (nested) list of the rows, as SciPy's.
    return new_t, _each(np.asarray(c, dtype=np.float64), one), k


def _inserted(t: np.ndarray, c: np.ndarray, k: int, x, m: int, periodic: bool):
    """(t, c) with the knot x inserted m times, c its n coefficients (any trailing axes)."""
    x = float(x)
    if x < t[k] or x > t[len(t) - k - 1]:
        raise ValueError(f"Cannot insert a knot at {x}.")
    for _ in range(m):
        t, c = _bspl.insert(t, c, k, x, periodic)
    return t, c
