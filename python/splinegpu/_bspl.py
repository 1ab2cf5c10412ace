"""B-spline arithmetic for `splinegpu.interpolate.BSpline` and `make_interp_spline`, in NumPy
float64 (or complex128): the pieces of a B-spline in SciPy's power form, the coefficients of
its derivatives and antiderivatives as SciPy's `splder`/`splantider` lay them out, B-spline
coefficients read off a fitted cubic's pieces, and the basis at points (knot spans, Cox-de
Boor values and derivatives, Taylor expansions) with knot insertion, for the fits of any
degree, the design matrix and `insert_knot`.

Notation: knots t_0 <= ... <= t_{n+k}, coefficients c_0 .. c_{n-1}, degree k; B_{i,k} is
supported on [t_i, t_{i+k+1}], and the base interval is [t_k, t_n].
"""

from __future__ import annotations

import numpy as np

from . import _native


def check(t: np.ndarray, c_length: int, k: int) -> None:
    """SciPy's rules for (t, c, k), each a ValueError naming what is wrong."""
    if t.ndim != 1:
        raise ValueError(f"t: the knots must be 1-D, got shape {t.shape}")
    check_many([t], [c_length], k, lambda s, what: what)


def check_many(ts: list, c_lengths: list, k: int, named) -> None:
    """SciPy's rules for every spline (ts[s] 1-D, c_lengths[s] coefficients, degree k), all
    splines at once; the first spline that breaks one raises a ValueError naming it:
    named(s, "t") or named(s, "c") is the name of its knots or coefficients."""
    if k < 0:
        raise ValueError(f"k: the degree must be >= 0, got {k}")
    if not ts:
        return
    lengths = np.array([len(t) for t in ts], dtype=np.int64)
    n = lengths - k - 1
    for s in np.flatnonzero(n < k + 1)[:1]:
        raise ValueError(f"{named(s, 't')}: need at least {2 * k + 2} knots for degree {k}, "
                         f"got {lengths[s]}")
    t = np.concatenate(ts)
    first = np.concatenate([[0], np.cumsum(lengths)])
    owner = np.repeat(np.arange(len(ts)), lengths)
    for s in owner[~np.isfinite(t)][:1]:
        raise ValueError(f"{named(s, 't')}: the knots must be finite")
    falls = np.flatnonzero(np.diff(t) < 0)
    for s in owner[falls[np.isin(falls + 1, first, invert=True)]][:1]:
        raise ValueError(f"{named(s, 't')}: the knots must be in non-decreasing order")
    for s in np.flatnonzero(~(t[first[:-1] + k] < t[first[:-1] + n]))[:1]:
        raise ValueError(f"{named(s, 't')}: the base interval [t[{k}], t[{n[s]}]] is empty "
                         f"(need at least two distinct knots there)")
    for s in np.flatnonzero(np.asarray(c_lengths) < n)[:1]:
        raise ValueError(f"{named(s, 'c')}: {c_lengths[s]} coefficients for {lengths[s]} knots "
                         f"of degree {k} (wants at least {n[s]})")


def cubic_knots_taken(t: np.ndarray) -> bool:
    """Whether the crate's cubic B-splines (kind "nurbs") take the knots `t` (which SciPy's
    rules passed): no value more than 4 times, none strictly inside the base interval
    [t_3, t_n] more than 3 times (SciPy takes those; the spline breaks there)."""
    t = np.asarray(t)
    if np.any(t[4:] == t[:-4]):
        return False
    triple = t[3:] == t[:-3]
    inside = (t[:-3] > t[3]) & (t[:-3] < t[-4])
    return not np.any(triple & inside)


def pieces(t: np.ndarray, c: np.ndarray, k: int):
    """The B-spline sum_i c_i B_{i,k} (c of shape (>= n, m)) as polynomial pieces: breakpoints
    (the distinct knots of the base interval) and coefficients (k + 1, P, m) in SciPy's power
    form; `many_pieces` of one spline."""
    return many_pieces([t], [c], k)[0]


def many_pieces(ts: list, cs: list, k: int) -> list:
    """Many B-splines (knots ts[s], coefficients cs[s] of shape (>= n_s, m)) as polynomial
    pieces, all splines' intervals at once: per spline (breakpoints, coefficients
    (k + 1, P_s, m)), piece j being sum_d coeff[k - d, j] (x - x_j)^d as SciPy's PPoly holds
    it.

    coeff[k - d, j] = f^(d)(x_j+) / d!: the d-th derivative is the spline of degree k - d with
    coefficients c^(d)_i = (k - d + 1) (c^(d-1)_i - c^(d-1)_{i-1}) / (t_{i+k-d+1} - t_i) on
    the same knots (a zero width: a zero term, whose basis function vanishes), evaluated at
    the interval's left end by de Boor's algorithm. The splines' knots are laid end to end
    with each one's coefficients beside its knots (padded to their count, as FITPACK lays
    them out), so that every index i, i - 1, i + p stays within its own spline."""
    lengths = np.array([len(t) for t in ts])
    first = np.concatenate([[0], np.cumsum(lengths)])
    t = np.concatenate(ts) if ts else np.zeros(0)
    m = cs[0].shape[1] if cs else 1
    c = np.zeros((len(t), m), dtype=np.result_type(*cs) if cs else np.float64)
    n = lengths - k - 1
    for s, cc in enumerate(cs):
        c[first[s]:first[s] + n[s]] = cc[:n[s]]
    owner = np.repeat(np.arange(len(ts)), lengths)
    local = np.arange(len(t)) - first[owner]
    j = np.flatnonzero((local >= k) & (local < n[owner]))
    j = j[t[j] < t[j + 1]]
    x = t[j]
    coeff = np.empty((k + 1, len(j), m), dtype=c.dtype)
    cd = c
    factorial = 1.0
    for d in range(k + 1):
        if d > 0:
            p = k - d + 1
            i = np.flatnonzero((local >= d) & (local < n[owner]))
            width = t[i + p] - t[i]
            step = np.zeros_like(cd)
            with np.errstate(divide="ignore", invalid="ignore"):
                step[i] = np.where((width > 0)[:, None],
                                   p * (cd[i] - cd[i - 1]) / width[:, None], 0.0)
            cd = step
            factorial *= d
        coeff[k - d] = _de_boor(t, cd, k - d, j, x) / factorial
    # Each spline's pieces, and its last breakpoint t_n.
    split = np.searchsorted(owner[j], np.arange(len(ts) + 1))
    return [(np.append(x[split[s]:split[s + 1]], t[first[s] + n[s]]),
             coeff[:, split[s]:split[s + 1]]) for s in range(len(ts))]


def _de_boor(t: np.ndarray, a: np.ndarray, q: int, j: np.ndarray, x: np.ndarray) -> np.ndarray:
    """sum_i a_i B_{i,q}(x) for each x in [t_j, t_{j+1}) (t_j < t_{j+1}), all at once: the
    coefficients a_{j-q} .. a_j blended q times, a_i <- (1 - w) a_{i-1} + w a_i with
    w = (x - t_i) / (t_{i+q+1-r} - t_i) at round r (never a zero width: t_{i+q+1-r} >= t_{j+1}
    > t_j >= t_i)."""
    d = [a[j - q + s] for s in range(q + 1)]
    for r in range(1, q + 1):
        for s in range(q, r - 1, -1):
            i = j - q + s
            w = ((x - t[i]) / (t[i + q + 1 - r] - t[i]))[:, None]
            d[s] = (1 - w) * d[s - 1] + w * d[s]
    return d[q]


def padded(t: np.ndarray, c: np.ndarray) -> np.ndarray:
    """c with zero rows up to len(t), as SciPy pads it before differentiating (FITPACK's
    layout: as many coefficients as knots)."""
    extra = t.shape[0] - c.shape[0]
    if extra <= 0:
        return c
    return np.concatenate([c, np.zeros((extra, *c.shape[1:]), dtype=c.dtype)])


def derivative(t: np.ndarray, c: np.ndarray, k: int, nu: int):
    """The nu-th derivative as (t, c, k) laid out as SciPy's `splder`: per order the
    coefficients p (c_i - c_{i-1}) / (t_{i+p} - t_i) (p the degree before it), the outer knot
    of each end dropped, the coefficients padded with zeros to the knots' length. A zero
    width (a knot repeated more than k times inside) is a ValueError, as SciPy's."""
    if nu > k:
        raise ValueError(f"nu: a spline of degree {k} has derivatives up to order {k}, got "
                         f"{nu}")
    c = padded(t, c)
    for _ in range(nu):
        width = t[k + 1:-1] - t[1:-k - 1]
        if np.any(width == 0):
            raise ValueError(f"The spline has internal repeated knots and is not "
                             f"differentiable {nu} times")
        shape = (-1,) + (1,) * (c.ndim - 1)
        step = (c[1:-1 - k] - c[:-2 - k]) * k / width.reshape(shape)
        c = np.concatenate([step, np.zeros((k, *c.shape[1:]), dtype=c.dtype)])
        t = t[1:-1]
        k -= 1
    return t, c, k


def antiderivative(t: np.ndarray, c: np.ndarray, k: int, nu: int):
    """The nu-th antiderivative (zero at t_0) as (t, c, k) laid out as SciPy's `splantider`:
    per order the knots t_0 and t_last repeated once more, the coefficients
    0, then d_i = sum_{l <= i} c_l (t_{l+k+1} - t_l) / (k + 1), then the last d_i k + 2 more
    times (to the knots' length)."""
    c = padded(t, c)
    for _ in range(nu):
        width = t[k + 1:] - t[:-k - 1]
        shape = (-1,) + (1,) * (c.ndim - 1)
        d = np.cumsum(c[:-k - 1] * width.reshape(shape), axis=0) / (k + 1)
        c = np.concatenate([np.zeros((1, *c.shape[1:]), dtype=c.dtype), d,
                            np.repeat(d[-1:], k + 2, axis=0)])
        t = np.concatenate([t[:1], t, t[-1:]])
        k += 1
    return t, c, k


def cubic_coefficients(t: np.ndarray, breaks: np.ndarray, coeff: np.ndarray,
                       period: float | None = None) -> np.ndarray:
    """The coefficients c_i (len(t) - 4, m) of the cubic B-spline on knots t equal to the
    piecewise cubic (breaks, coeff (4, P, m) in SciPy's power form), read off by blossoming:
    c_i is the polar form of the polynomial on B_i's support at (t_{i+1}, t_{i+2}, t_{i+3}),
    for a + b v + c v^2 + d v^3 (v local to its piece)
        a + b (v1 + v2 + v3) / 3 + c (v1 v2 + v1 v3 + v2 v3) / 3 + d v1 v2 v3.
    The piece is the one at the middle of the wider of [t_{i+1}, t_{i+2}] and
    [t_{i+2}, t_{i+3}] (inside the support, and the arguments no farther from it than needed);
    with a `period`, a middle outside [breaks_0, breaks_last] is wrapped into it."""
    i = np.arange(len(t) - 4)
    u1, u2, u3 = t[i + 1], t[i + 2], t[i + 3]
    middle = np.where(u3 - u2 >= u2 - u1, (u2 + u3) / 2, (u1 + u2) / 2)
    shift = np.zeros_like(middle)
    if period is not None:
        shift = breaks[0] + np.mod(middle - breaks[0], period) - middle
    p = np.clip(np.searchsorted(breaks, middle + shift, side="right") - 1, 0,
                coeff.shape[1] - 1)
    origin = breaks[p] - shift
    v1, v2, v3 = ((u - origin)[:, None] for u in (u1, u2, u3))
    cubic, square, linear, constant = coeff[0, p], coeff[1, p], coeff[2, p], coeff[3, p]
    return (constant + linear * (v1 + v2 + v3) / 3 + square * (v1 * v2 + v1 * v3 + v2 * v3) / 3
            + cubic * (v1 * v2 * v3))


def intervals(t: np.ndarray, k: int, x: np.ndarray) -> np.ndarray:
    """For each x, its knot span: the l with t_l <= x < t_{l+1} among k <= l <= n - 1
    (n = len(t) - k - 1), the first below t_k and the last at and above t_n, as SciPy's
    evaluation picks it."""
    n = len(t) - k - 1
    return np.clip(np.searchsorted(t, x, side="right") - 1, k, n - 1)


def basis(t: np.ndarray, k: int, x: np.ndarray, span: np.ndarray, nu: int = 0) -> np.ndarray:
    """The nu-th derivatives of the k + 1 B-splines B_{l-k,k} .. B_{l,k} that do not vanish
    on [t_l, t_{l+1}], at each x (l its `span`), as (len(x), k + 1): the workspace's one
    Cox-de Boor recursion (bsplines::de_boor::basis_in, through the extension), which raises
    the degree from 0 (B_{l,0} = 1) to k - nu by
        B_{i,p}(x) = w_{i,p} B_{i,p-1} + (1 - w_{i+1,p}) B_{i+1,p-1},
        w_{i,p} = (x - t_i) / (t_{i+p} - t_i),
    and applies the derivative for each of the last nu degrees,
        B'_{i,p} = p (B_{i,p-1} / (t_{i+p} - t_i) - B_{i+1,p-1} / (t_{i+p+1} - t_{i+1})),
    a term over a zero width being zero (its function is zero)."""
    return _native.bspline_basis(np.ascontiguousarray(t, dtype=np.float64), int(k),
                                 np.ascontiguousarray(x, dtype=np.float64),
                                 np.ascontiguousarray(span, dtype=np.int64), int(nu))


def insert(t: np.ndarray, c: np.ndarray, k: int, x: float, periodic: bool):
    """Knot x inserted once (Boehm): the knots t with x after t_l (t_l <= x < t_{l+1}, the last
    interval at x = t_n) and the coefficients, one more, of the same spline,
        c'_i = c_i (i <= l - k),   c'_i = a_i c_i + (1 - a_i) c_{i-1} (l - k < i <= l),
        c'_i = c_{i-1} (i > l),    a_i = (x - t_i) / (t_{i+k} - t_i).
    A periodic spline (FITPACK's rule, so that the result equals its `insert(per=1)`) then
    repeats its first or last k coefficients and knots one period on, when the new knot lies
    among the last or the first 2k + 1."""
    n = len(t)
    span = int(intervals(t, k, np.array([x]))[0])
    while span > k and t[span] == t[span + 1]:
        # x at the base interval's end, already a knot there: the last non-empty interval.
        span -= 1
    if not t[span] < t[span + 1]:
        raise ValueError(f"Cannot insert a knot at {x}.")
    if periodic and span + 1 <= 2 * k and span + 1 >= n - 2 * k:
        raise ValueError("Not enough internal knots.")
    tt = np.concatenate([t[:span + 1], [x], t[span + 1:]])
    cc = np.concatenate([c, c[-1:]])
    cc[span + 1:] = c[span:]
    for i in range(span, span - k, -1):
        a = (x - tt[i]) / (tt[i + k + 1] - tt[i])
        cc[i] = a * c[i] + (1 - a) * c[i - 1]
    if periodic:
        count = n + 1
        shift = count - 2 * k - 1
        period = tt[count - k - 1] - tt[k]
        if span + 2 > shift:
            for m in range(k):
                cc[m] = cc[m + shift]
                tt[k - 1 - m] = tt[count - k - 2 - m] - period
        elif span + 2 <= 2 * k + 1:
            for m in range(k):
                cc[m + shift] = cc[m]
                tt[count - k + m] = tt[k + 1 + m] + period
    return tt, cc


def taylor(t: np.ndarray, c: np.ndarray, k: int, at: np.ndarray) -> np.ndarray:
    """The spline sum_i c_i B_{i,k} (c of shape (>= n, m)) expanded at each point of `at` in
    SciPy's power form: (k + 1, len(at), m), row k - d holding f^(d)(a+) / d! from the span of
    each a (the end spans past the base interval)."""
    span = intervals(t, k, at)
    out = np.empty((k + 1, len(at), c.shape[1]), dtype=c.dtype)
    factorial = 1.0
    for d in range(k + 1):
        factorial *= max(d, 1)
        weights = basis(t, k, at, span, d)
        values = sum(weights[:, r, None] * c[span - k + r] for r in range(k + 1))
        out[k - d] = values / factorial
    return out
