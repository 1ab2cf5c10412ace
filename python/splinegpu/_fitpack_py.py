"""SciPy's FITPACK doors with tck tuples: `splrep`, `splprep`, `splev`, `splint`, `sproot`,
`splder` and `splantider`, answered by this package's B-splines (a tck is (t, c, k), c
padded with zeros to len(t), as SciPy's; a parametric one holds a list of coordinate
arrays). A BSpline given in place of a tck is answered with a BSpline, as SciPy does.

Smoothing (s > 0) of splrep and splprep is FITPACK's curfit, parcur, percur and clocur
themselves (`bsplines::curfit`, `bsplines::percur`: the same knots, coefficients, fp and ier
as SciPy's for the same data); splrep's task=1 goes on with the last smoothing search for
another s (curfit's iopt = 1). `per=1` fits periodic splines: the period x[-1] - x[0], the
last point standing for the first (its value is not fitted; splprep sets it to the first).
task=-1 fits least squares on given knots. Refused by name (NotImplementedError): splrep's
task=1 with per=1, splprep's task=1, and given knots with per=1."""

from __future__ import annotations

import warnings

import numpy as np

from . import _bspl, _collocation, _native
from ._bsplines import BSpline, make_interp_spline
from ._fitpack_repro import chord_lengths, fpcheck, make_splprep, make_splrep
from ._helpers import _aligned
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


# FITPACK's ier and SciPy's words for it (its `_iermess`): the message full_output returns,
# the warning for 1 to 3 and for every ier when quiet=0.
_IERMESS = {
    0: "The spline has a residual sum of squares fp such that abs(fp-s)/s<=0.001",
    -1: "The spline is an interpolating spline (fp=0)",
    -2: "The spline is weighted least-squares polynomial of degree k.\n"
        "fp gives the upper bound fp0 for the smoothing factor s",
    1: "The required storage space exceeds the available storage space.\n"
       "Probable causes: data (x,y) size is too small or smoothing parameter\n"
       "s is too small (fp>s).",
    2: "A theoretically impossible result when finding a smoothing spline\n"
       "with fp = s. Probable cause: s too small. (abs(fp-s)/s>0.001)",
    3: "The maximal number of iterations (20) allowed for finding smoothing\n"
       "spline with fp=s has been reached. Probable cause: s too small.\n"
       "(abs(fp-s)/s>0.001)",
}

# Where splrep's last smoothing search stopped (`_native.fit_curfit`'s state, None: from the
# polynomial) and its nest, for task=1; None before any fit (SciPy's `_curfit_cache`).
_last_search: tuple | None = None


def curfit(x: np.ndarray, y: np.ndarray, w, xb: float, xe: float, k: int, s: float,
            nest: int, parametric: bool = False, periodic: bool = False, state=None):
    """FITPACK's curfit (parcur where `parametric`; percur, clocur where `periodic`) with
    s > 0 of (x, y (m, d)): (t, c (n, d), fp, ier, state)."""
    weights = np.ones_like(x) if w is None else np.asarray(w, dtype=np.float64)
    return _native.fit_curfit(_aligned(x, "x"), np.ascontiguousarray(y, dtype=np.float64),
                              _aligned(weights, "w"), float(xb), float(xe), k, float(s),
                              int(nest), parametric, periodic, state)


def _reported(result, fp: float, ier: int, full_output, quiet, k: int, n: int, m: int, s):
    """splrep's and splprep's answer for FITPACK's ier, as SciPy's: with full_output (result,
    fp, ier, message); else result, warning for ier 1 to 3 (and every ier when quiet=0)."""
    message = _IERMESS[ier]
    if ier <= 0 and not quiet:
        warnings.warn(RuntimeWarning(f"{message}\tk={k} n={n} m={m} fp={fp} s={s}"),
                      stacklevel=3)
    if full_output:
        return result, fp, ier, message
    if ier > 0:
        warnings.warn(RuntimeWarning(message), stacklevel=3)
    return result


def splrep(x, y, w=None, xb=None, xe=None, k: int = 3, task: int = 0, s=None, t=None,
           full_output: int = 0, per: int = 0, quiet: int = 1):
    """`scipy.interpolate.splrep`: the tck of the interpolating (s = 0), smoothing (s > 0,
    FITPACK's curfit) or least-squares (interior knots t) spline of (x, y); task=1 smooths
    for this s going on from the last smoothing search (curfit's iopt = 1). full_output
    adds (fp, ier, msg); ier 1 to 3 warn otherwise, as SciPy's."""
    global _last_search
    if not -1 <= task <= 1:
        raise TypeError("task must be -1, 0 or 1")
    if t is not None:
        task = -1
    if task == -1 and t is None:
        raise TypeError("Knots must be given for task=-1")
    if task == 1 and per:
        raise NotImplementedError("task: periodic splrep going on from the last search "
                                  "(task=1 with per=1) is not implemented here")
    if task == 1 and _last_search is None:
        raise TypeError("must call with task=1 only after call with task=0,-1")
    x = _check_finite_input(x, "x")
    y = _check_finite_input(y, "y")
    if y.ndim != 1:
        raise ValueError(f"y: one value per x (a 1-D array), got shape {y.shape}")
    m = len(x)
    if m <= k:
        raise TypeError(f"m > k must hold: {m} points for k = {k}")
    if s is None:
        s = _default_s(m, w)
    if per:
        if t is not None:
            raise NotImplementedError("t: periodic splrep with given knots (per=1 and t) "
                                      "is not implemented here")
        # percur: the last point stands for the first (its y is not fitted).
        y = np.concatenate([y[:-1], y[:1]])
        columns, fp, ier = _periodic(x, y[:, None], w, k, s)
        spline = BSpline.construct_fast(columns.t, columns.c[:, 0], k)
        result = (spline.t, _padded(spline.t, spline.c), spline.k)
        if s == 0:
            fp = _fp(x[:-1], y[:-1], w, spline)
        return _reported(result, fp, ier, full_output, quiet, k, len(spline.t), m, s)
    if task == 1 and _last_search is not None:
        state, nest = _last_search
    else:
        state, nest = None, max(m + k + 1, 2 * k + 3)
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
        # A later task=1 searches afresh, with room for as many knots as these.
        _last_search = (None, len(knots))
        fp, ier = _fp(x, y, w, spline), 0
    elif s == 0:
        spline = (make_interp_spline(x, y, k=k) if w is None and xb is None and xe is None
                  else make_splrep(x, y, w=w, xb=xb, xe=xe, k=k, s=0))
        _last_search = (None, nest)
        fp, ier = _fp(x, y, w, spline), -1
    else:
        knots, c, fp, ier, state = curfit(x, y[:, None], w, x[0] if xb is None else xb,
                                           x[-1] if xe is None else xe, k, s, nest,
                                           state=state)
        spline = BSpline.construct_fast(knots, c[:, 0], k)
        _last_search = (state, nest)
    result = (spline.t, _padded(spline.t, spline.c), spline.k)
    return _reported(result, fp, ier, full_output, quiet, k, len(spline.t), m, s)


def _fp(x: np.ndarray, y: np.ndarray, w, spline: BSpline) -> float:
    """FITPACK's fp: sum (w_i (y_i - s(x_i)))^2 over the points given (w's first len(x))."""
    weights = np.ones_like(x) if w is None else np.asarray(w, dtype=np.float64)[:len(x)]
    return float(np.sum((weights * (y - spline(x))) ** 2))


def _periodic(x: np.ndarray, y: np.ndarray, w, k: int, s: float, nest=None,
              parametric: bool = False):
    """FITPACK's periodic fit of y ((m, d), y[-1] = y[0]) over x, period x[-1] - x[0]: the
    interpolating spline on the periodic knots for s = 0, else FITPACK's percur (clocur
    where `parametric`) with room for nest knots (None: m + 2k; at least 2k + 3). Returns
    (spline with c (n - k - 1, d), fp, ier)."""
    if s == 0:
        t = _collocation.periodic(x, k)
        if k == 1:
            # percur's k = 1: the coefficients are the values.
            spline = BSpline.construct_fast(t, y, 1)
        else:
            spline = make_interp_spline(x, y, k=k, bc_type="periodic")
        return spline, 0.0, -1
    m = len(x)
    nest = max(m + 2 * k if nest is None or nest < 0 else int(nest), 2 * k + 3)
    knots, c, fp, ier, _ = curfit(x, y, w, x[0], x[-1], k, s, nest, parametric=parametric,
                                   periodic=True)
    return BSpline.construct_fast(knots, c, k), fp, ier


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
    if w is not None and (len(np.atleast_1d(w)) != m
                          or not np.all(np.asarray(w, dtype=np.float64) > 0)):
        # parcur and clocur take positive weights only.
        raise ValueError("Invalid inputs: w must hold one positive weight per point")
    if task == -1:
        u = chord_lengths(x.T) if u is None else np.asarray(u, dtype=np.float64)
        inner = np.asarray(t, dtype=np.float64)[k + 1:len(t) - k - 1]
        knots = np.concatenate([[u[0] if ub is None else ub] * (k + 1), inner,
                                [u[-1] if ue is None else ue] * (k + 1)])
        spline = make_lsq_spline(u, x.T, knots, k, w=w)
    elif per:
        u = chord_lengths(x.T) if u is None else np.asarray(u, dtype=np.float64)
        spline, fp, ier = _periodic(u, x.T.copy(), w, k, s, nest, parametric=True)
    elif s == 0:
        spline, u = make_splprep(points, u=u, k=k, s=0)
    else:
        spline, u, fp, ier = _parcur(x, w, u, ub, ue, k, s, nest)
    # SciPy's parametric tck keeps each coordinate's n coefficients unpadded.
    tck = [spline.t, list(np.asarray(spline.c).T), spline.k]
    if s == 0 or task == -1:
        fp = _fp_curve(u[:-1], x[:, :-1], None if w is None else np.asarray(w)[:-1], spline) \
            if per else _fp_curve(u, x, w, spline)
        ier = -1 if s == 0 and task == 0 else 0
    return _reported((tck, u), fp, ier, full_output, quiet, k, len(spline.t), m, s)


def _parcur(x: np.ndarray, w, u, ub, ue, k: int, s: float, nest):
    """FITPACK's parcur with s > 0 of the points x (d, m) at u (None: the chord lengths,
    [ub, ue] = [0, 1]), room for nest knots (None: m + 2k; negative: m + k + 1; at least
    2k + 3): (spline with c (n, d), u, fp, ier)."""
    m = x.shape[1]
    if u is None:
        u, ub, ue = chord_lengths(x.T), 0.0, 1.0
    else:
        u = np.asarray(u, dtype=np.float64)
        ub = u[0] if ub is None else float(ub)
        ue = u[-1] if ue is None else float(ue)
    if ub > u[0] or ue < u[-1]:
        raise ValueError(f"Invalid inputs: ub <= u[0] and u[-1] <= ue must hold, got "
                         f"[{ub}, {ue}] around [{u[0]}, {u[-1]}]")
    if nest is None:
        nest = m + 2 * k
    elif nest < 0:
        nest = m + k + 1
    nest = max(int(nest), 2 * k + 3)
    knots, c, fp, ier, _ = curfit(u, x.T, w, ub, ue, k, s, nest, parametric=True)
    return BSpline.construct_fast(knots, c, k), u, fp, ier


def _fp_curve(u: np.ndarray, x: np.ndarray, w, spline: BSpline) -> float:
    """parcur's fp of a curve: sum_i w_i^2 |x_i - s(u_i)|^2 (x (d, m))."""
    weights = np.ones(x.shape[1]) if w is None else np.asarray(w, dtype=np.float64)
    along_u = BSpline.construct_fast(spline.t, np.asarray(spline.c), spline.k)
    return float(np.sum(weights ** 2 * np.sum((x.T - along_u(u)) ** 2, axis=1)))


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
    if c.shape[-1] < n:
        raise ValueError(f"c: {c.shape[-1]} coefficients, must be >=n-k-1 = {n}")
    integrals = bspline_integrals(np.asarray(t, dtype=np.float64), k, float(a), float(b))

    def one(coefficients):
        # FITPACK's splint: the coefficients times the B-splines' integrals, summed in order.
        total = 0.0
        for ci, bi in zip(coefficients[:n], integrals):
            total += float(ci) * float(bi)
        return total

    value = _each(c, one)
    if full_output:
        return value, integrals
    return value


def bspline_integrals(t: np.ndarray, k: int, a: float, b: float) -> np.ndarray:
    """The integral of each B-spline B_{i,k} over [a, b], clipped to [t_k, t_{n-k-1}] (b < a:
    the negative), as FITPACK's fpintb computes them: at each end, the values there of the
    B-splines of degree k + 1 on the same knots (the recurrence carried one degree further),
    whose differences over [a, b] plus 1 for every B-spline wholly inside, times
    (t_{i+k+1} - t_i) / (k + 1), are the integrals."""
    nk1 = len(t) - k - 1
    out = np.zeros(nk1)
    if a == b:
        return out
    sign = 1.0
    if a > b:
        a, b, sign = b, a, -1.0
    a, b = max(a, t[k]), min(b, t[nk1])
    if a > b:
        return out

    # Coincident knots give inf or NaN there, as in FITPACK, not an exception.
    with np.errstate(divide="ignore", invalid="ignore"):
        return sign * _integrals_from(t, out, k, (a, b))


def _integrals_from(t: np.ndarray, out: np.ndarray, k: int, ends: tuple) -> np.ndarray:
    """`bspline_integrals`' recurrence between the ends, into out (FITPACK's 1-based knot
    numbers: t(i) is t[i - 1])."""
    nk1, k1 = len(t) - k - 1, k + 1

    def knot(i: int) -> np.float64:
        return t[i - 1]

    first = 0
    span = k1
    for end, arg in enumerate(ends):
        while not (arg < knot(span + 1) or span == nk1):
            span += 1
        aint = [0.0] * k1
        aint[0] = (arg - knot(span)) / (knot(span + 1) - knot(span))
        h, h1 = [0.0] * (k1 + 1), [1.0] + [0.0] * k1
        for j in range(1, k + 1):
            h[0] = 0.0
            for i in range(1, j + 1):
                li, lj = span + i, span + i - j
                f = h1[i - 1] / (knot(li) - knot(lj))
                h[i - 1] += f * (knot(li) - arg)
                h[i] = f * (arg - knot(lj))
            for i in range(1, j + 2):
                li, lj = span + i, span + i - j - 1
                aint[i - 1] += h[i - 1] * (arg - knot(lj)) / (knot(li) - knot(lj))
                h1[i - 1] = h[i - 1]
        lowest = span - k
        if end == 0:
            first = lowest
            for i in range(k1):
                out[lowest - 1 + i] = -aint[i]
        else:
            for i in range(k1):
                out[lowest - 1 + i] += aint[i]
            for i in range(first, lowest):
                out[i - 1] += 1.0
    for i in range(1, nk1 + 1):
        out[i - 1] *= (knot(i + k1) - knot(i)) / k1
    return out


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
