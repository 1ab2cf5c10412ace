"""Interpolating B-splines of any degree k (SciPy's `make_interp_spline` beyond the cubic fast
path): the knots SciPy chooses, and the coefficients from the collocation system

    sum_i c_i B_{i,k}^(d)(x_j) = y_j  (d = 0 at the data, the ends' orders at x_0 and x_last),

banded with k + 1 entries a row, solved by elimination with pivoting inside the band (the
extension's `solve_banded`, O(n k^2)); periodic splines as a cyclic system, its corner entries
taken out by the Woodbury identity. Columns of y (real and imaginary parts of a complex y
alike) share one elimination.
"""

from __future__ import annotations

import numpy as np

from . import _bspl, _native


def not_a_knot(x: np.ndarray, k: int) -> np.ndarray:
    """SciPy's default knots: x (odd k) or the midpoints of x (even k), without (k + 1) // 2
    (or k // 2) of them at each end, between the ends repeated k + 1 times."""
    if k % 2 == 1:
        inner, cut = x, (k + 1) // 2
    else:
        inner, cut = (x[1:] + x[:-1]) / 2, k // 2
    inner = inner[cut:len(inner) - cut]
    return np.concatenate([np.repeat(x[:1], k + 1), inner, np.repeat(x[-1:], k + 1)])


def with_ends(x: np.ndarray, k: int) -> np.ndarray:
    """Knots for conditions at the ends: every x, each end k more times."""
    return np.concatenate([np.repeat(x[:1], k), x, np.repeat(x[-1:], k)])


def periodic(x: np.ndarray, k: int) -> np.ndarray:
    """SciPy's periodic knots: x (for even k every inner x moved back half the step before
    it), and k knots past each end repeating the other end's steps, cycling through them
    when there are fewer than k."""
    xc = np.array(x, dtype=np.float64)
    n = len(xc)
    if k % 2 == 0:
        xc[1:-1] -= np.diff(xc)[:-1] / 2
    dx = np.diff(xc)
    t = np.zeros(n + 2 * k)
    t[k:n + k] = xc
    for i in range(k):
        t[k - i - 1] = t[k - i] - dx[-(i % (n - 1)) - 1]
        t[n + k + i] = t[n + k + i - 1] + dx[i % (n - 1)]
    return t


def _banded(first: np.ndarray, rows: np.ndarray, rhs: np.ndarray) -> np.ndarray | None:
    # Aligned and C-contiguous, as the extension takes them (y may come misaligned from a
    # network buffer).
    return _native.solve_banded(np.require(first, np.int64, ["C", "A"]),
                                np.require(rows, np.float64, ["C", "A"]),
                                np.require(rhs, np.float64, ["C", "A"]))


def singular() -> np.linalg.LinAlgError:
    return np.linalg.LinAlgError("Colocation matrix is singular.")


def coefficients(x, y, t, k: int, left: list, right: list) -> np.ndarray:
    """c (len(t) - k - 1, m) with the spline through (x, y (n, m), real) and the end
    conditions `left` and `right` (lists of (order, values (m,))) met."""
    nt = len(t) - k - 1
    rows = []
    first = []
    for where, conditions in ((x[:1], left), (x, None), (x[-1:], right)):
        span = _bspl.intervals(t, k, where)
        for order in ([0] if conditions is None else [o for o, _ in conditions]):
            rows.append(_bspl.basis(t, k, where, span, order))
            first.append(span - k)
    rhs = np.concatenate([np.array([v for _, v in left]).reshape(-1, y.shape[1]), y,
                          np.array([v for _, v in right]).reshape(-1, y.shape[1])])
    c = _banded(np.concatenate(first), np.concatenate(rows), rhs)
    if c is None or rhs.shape[0] != nt:
        raise singular()
    return c


def periodic_coefficients(x, y, t, k: int) -> np.ndarray:
    """c (n + k - 1, m) of the periodic spline through (x, y (n, m), real; y_last = y_0) on
    periodic knots: the n - 1 free coefficients c_0 .. c_{n-2} (c_{j+n-1} = c_j) from the
    cyclic system at x_0 .. x_{n-2}, the row of x_j in knot span l touching c_{l-k} .. c_l
    (indices mod n - 1)."""
    size = len(x) - 1
    span = _bspl.intervals(t, k, x[:-1])
    rows = _bspl.basis(t, k, x[:-1], span)
    columns = (span - k)[:, None] + np.arange(k + 1)[None, :]
    rhs = y[:-1]
    free = None
    if size > 2 * (k + 1):
        free = _woodbury(rows, columns, rhs, size)
    if free is None:
        dense = np.zeros((size, size))
        np.add.at(dense, (np.repeat(np.arange(size), k + 1), (columns % size).ravel()),
                  rows.ravel())
        try:
            free = np.linalg.solve(dense, rhs)
        except np.linalg.LinAlgError:
            raise singular() from None
    return np.concatenate([free, free[np.arange(k) % size]])


def _woodbury(rows, columns, rhs, size: int) -> np.ndarray | None:
    """The cyclic system solved as its band B plus the wrapped corner entries U V^T:
    x = z - Z (I + V^T Z)^-1 V^T z with B z = rhs and B Z = U; None where B or the small
    system is singular. The unknowns are first turned k // 2 places, so that each row's
    largest entries (the middle of its k + 1) lie on B's diagonal and the corners are split
    between both ends: B is then as well conditioned as the collocation itself."""
    k1 = rows.shape[1]
    turn = (k1 - 1) // 2
    turned = columns - turn
    wraps = (turned < 0) | (turned >= size)
    band = np.where(wraps, 0.0, rows)
    # Each row's window of k + 1 columns, kept inside the matrix.
    first = np.clip(turned[:, 0], 0, size - k1)
    shift = turned[:, 0] - first
    shifted = np.zeros_like(band)
    for r in range(k1):
        target = r + shift
        keep = (target >= 0) & (target < k1)
        shifted[np.flatnonzero(keep), target[keep]] = band[keep, r]
    corner_rows, corner_slots = np.nonzero(wraps)
    u = np.zeros((size, len(corner_rows)))
    u[corner_rows, np.arange(len(corner_rows))] = rows[corner_rows, corner_slots]
    solved = _banded(first, shifted, np.concatenate([rhs, u], axis=1))
    if solved is None:
        return None
    z, zu = solved[:, :rhs.shape[1]], solved[:, rhs.shape[1]:]
    v_columns = turned[corner_rows, corner_slots] % size
    small = np.eye(len(corner_rows)) + zu[v_columns]
    try:
        x = z - zu @ np.linalg.solve(small, z[v_columns])
    except np.linalg.LinAlgError:
        return None
    # Back from the turned order: coefficient c is unknown (c - turn) mod size.
    return x[(np.arange(size) - turn) % size]
