"""`PPoly`: SciPy's piecewise polynomial in the power basis, any degree, evaluated in NumPy
(float64 or complex128) on the CPU. The cubic splines of `splinegpu.interpolate` are PPoly
subclasses that evaluate through a context; what SciPy answers through PPoly (antiderivatives,
integrals, roots and solve) they answer here.

Piece i between x_i and x_{i+1} is sum_m c[m, i] (x - x_i)^(k-1-m), the highest power first,
as SciPy holds it; x increases or, as SciPy allows, decreases.
"""

from __future__ import annotations

import math

import numpy as np

from . import _bspl, _native
from ._helpers import _extrapolate, _f64, _is_named


class Piecewise:
    """What SciPy's PPoly and BPoly share (its `_PPolyBase`): c of shape (k, m, ...) (with
    `axis` a: k and m at c's axes a and a + 1), x of m + 1 strictly increasing (or decreasing,
    as SciPy's) breakpoints, `c` held as (k, m, ...); the checks, `construct_fast`, calls
    (through `_values`, the basis's own evaluation) and `extend`."""

    def _values(self, c: np.ndarray, flat: np.ndarray, nu: int) -> np.ndarray:
        """Derivative nu of the pieces c (k, m, columns) at flat: (len, columns)."""
        raise NotImplementedError

    def _piece_of(self, flat: np.ndarray) -> np.ndarray:
        """The piece each value of flat evaluates in: the last breakpoint at or before it (the
        first and last pieces taking what lies beyond the ends); for descending breakpoints
        piece i spans [x_{i+1}, x_i], the one whose start is the first at or above the value."""
        x = self.x
        if x[0] <= x[-1]:
            i = np.searchsorted(x, flat, side="right") - 1
        else:
            i = len(x) - 1 - np.searchsorted(x[::-1], flat, side="left")
        return np.clip(i, 0, len(x) - 2)

    def __init__(self, c, x, extrapolate=None, axis: int = 0):
        c = np.asarray(c)
        if c.dtype.kind not in "biufc":
            raise TypeError(f"c: must be numbers, got an array of {c.dtype}")
        c = np.array(c, dtype=np.complex128 if c.dtype.kind == "c" else np.float64)
        x = np.array(x, dtype=np.float64)
        if c.ndim < 2:
            raise ValueError(f"c: must have at least 2 dimensions (k, m, ...), got {c.ndim}")
        if isinstance(axis, bool) or not isinstance(axis, (int, np.integer)) or not (
                0 <= axis < c.ndim - 1):
            raise ValueError(f"axis: must be an integer from 0 to {c.ndim - 2}, got {axis!r}")
        # As SciPy's: with axis a, c's k and m are its axes a and a + 1; held as (k, m, ...).
        c = np.moveaxis(np.moveaxis(c, axis + 1, 0), axis + 1, 0)
        if x.ndim != 1 or len(x) < 2:
            raise ValueError(f"x: must be 1-D with at least 2 breakpoints, got shape {x.shape}")
        if c.shape[0] == 0:
            raise ValueError("c: the polynomial order must be at least 0 (k >= 1)")
        if c.shape[1] != len(x) - 1:
            raise ValueError(f"c: {c.shape[1]} pieces for {len(x)} breakpoints (wants "
                             f"{len(x) - 1})")
        if not np.all(np.isfinite(x)) or not (np.all(np.diff(x) > 0) or
                                              np.all(np.diff(x) < 0)):
            raise ValueError("x: must be finite and strictly increasing or decreasing")
        self.c, self.x = np.ascontiguousarray(c), x
        self.axis = int(axis)
        extrapolate = _extrapolate(extrapolate)
        self.extrapolate = True if extrapolate is None else extrapolate

    @classmethod
    def _made(cls, c, x, extrapolate, axis):
        poly = cls.__new__(cls)
        poly.c, poly.x, poly.extrapolate, poly.axis = c, x, extrapolate, axis
        return poly

    @classmethod
    def construct_fast(cls, c, x, extrapolate=None, axis: int = 0):
        """A polynomial of c (k, m, ...) and x taken as they are, without checks, as SciPy's."""
        return cls._made(c, x, True if extrapolate is None else extrapolate, axis)

    def _column_c(self) -> np.ndarray:
        """c as (k, m, columns)."""
        c = self.c
        return c.reshape(c.shape[0], c.shape[1], math.prod(c.shape[2:]))

    def _like(self, c: np.ndarray, x: np.ndarray, extrapolate):
        """A polynomial made from this one (a derivative, an antiderivative)."""
        return self._made(c, x, extrapolate, self.axis)

    def __call__(self, x, nu: int = 0, extrapolate=None) -> np.ndarray:
        """Derivative nu (>= 0) at x, shape x.shape + c.shape[2:] (x's axes moved to `axis`);
        NaN at NaN, and outside the breakpoints when extrapolate is False."""
        if not isinstance(nu, (int, np.integer)) or nu < 0:
            raise ValueError(f"nu: must be an integer >= 0, got {nu!r}")
        nu = int(nu)
        mode = self.extrapolate if extrapolate is None else _extrapolate(extrapolate)
        x = np.asarray(x, dtype=np.float64)
        flat = x.ravel()
        lo, hi = min(self.x[0], self.x[-1]), max(self.x[0], self.x[-1])
        if mode == "periodic":
            flat = self.x[0] + np.mod(flat - self.x[0], self.x[-1] - self.x[0])
        out = self._values(self._column_c(), flat, nu)
        if mode is False:
            out[~((flat >= lo) & (flat <= hi))] = np.nan
        out[np.isnan(flat)] = np.nan
        out = out.reshape(x.shape + self.c.shape[2:])
        if self.axis != 0 and x.ndim > 0:
            axes = list(range(out.ndim))
            axes = axes[x.ndim:x.ndim + self.axis] + axes[:x.ndim] + axes[x.ndim + self.axis:]
            out = out.transpose(axes)
        return out

    def extend(self, c, x) -> None:
        """Adds pieces c (k', m', ...) on the right (x[0] >= self.x[-1]) or the left
        (x[-1] <= self.x[0]) with breakpoints x (m' values: the new pieces' far ends), as
        SciPy's `extend`; a lower degree's missing leading coefficients are zeros."""
        c, x = np.asarray(c), np.asarray(x, dtype=np.float64)
        if c.ndim != self.c.ndim or c.shape[2:] != self.c.shape[2:]:
            raise ValueError(f"c: shape {c.shape} does not match the polynomial's "
                             f"{self.c.shape}")
        if x.ndim != 1 or x.shape[0] != c.shape[1]:
            raise ValueError(f"x: must be 1-D with one breakpoint per new piece "
                             f"({c.shape[1]}), got shape {x.shape}")
        if c.size == 0:
            return
        if np.any(np.diff(x) <= 0):
            raise ValueError("x: must be strictly increasing")
        if x[0] > self.x[-1]:
            right = True
        elif x[-1] < self.x[0]:
            right = False
        else:
            raise ValueError("x: must lie wholly to the right or to the left of the "
                             "breakpoints")
        dtype = np.result_type(self.c, c)
        k = max(c.shape[0], self.c.shape[0])
        merged = np.zeros((k, self.c.shape[1] + c.shape[1], *self.c.shape[2:]), dtype=dtype)
        old, new = (slice(0, self.c.shape[1]), slice(self.c.shape[1], None)) if right else \
            (slice(c.shape[1], None), slice(0, c.shape[1]))
        merged[k - self.c.shape[0]:, old] = self.c
        merged[k - c.shape[0]:, new] = c
        self.c = merged
        self.x = np.concatenate([self.x, x] if right else [x, self.x])


class PPoly(Piecewise):
    """`scipy.interpolate.PPoly(c, x, extrapolate=None, axis=0)`: c of shape (k, m, ...) and
    x as `Piecewise` takes them. Calls with nu >= 0, `derivative`, `antiderivative`,
    `integrate`, `solve`, `roots`, `extend`, `from_spline`, `from_bernstein_basis` and
    `construct_fast` answer as SciPy's (roots by the eigenvalues of each piece's companion
    matrix, as SciPy finds them, refined by one Newton step). Evaluated, integrated and
    antidifferentiated in the extension in float64 (complex c as its two parts; descending
    breakpoints in NumPy)."""

    # Whether c comes from the package's own fit (its rounding where SciPy's has exact zeros:
    # roots take a piece's degree from its terms that are not negligible) rather than given.
    _fitted = False

    @classmethod
    def from_spline(cls, tck, extrapolate=None) -> PPoly:
        """The B-spline `tck` (a BSpline, ours or SciPy's, or a (t, c, k) tuple) as SciPy's
        PPoly.from_spline makes it: one piece per knot interval (len(t) - 1 of them, empty
        ones too, breakpoints t), each the spline's Taylor expansion at its start."""

        if all(hasattr(tck, name) for name in ("t", "c", "k")):
            t, c, k = tck.t, tck.c, tck.k
            if extrapolate is None:
                extrapolate = tck.extrapolate
        else:
            t, c, k = tck
        t = np.asarray(t, dtype=np.float64)
        c = np.asarray(c)
        c = c.astype(np.complex128 if c.dtype.kind == "c" else np.float64)
        trailing = c.shape[1:]
        columns = _bspl.padded(t, c).reshape(max(len(c), len(t)), -1)
        coeff = _bspl.taylor(t, columns, k, t[:-1])
        return cls.construct_fast(coeff.reshape((k + 1, len(t) - 1, *trailing)), t,
                                  extrapolate)

    @classmethod
    def from_bernstein_basis(cls, bp, extrapolate=None) -> PPoly:
        """SciPy's BPoly `bp` in the power basis: on a piece of width h,
        sum_a b_a C(k, a) u^a (1 - u)^(k - a) with u = s / h has the coefficient
        sum_{a <= d} b_a C(k, a) C(k - a, d - a) (-1)^(d - a) / h^d of s^d."""
        if not _is_named(bp, "BPoly"):
            raise TypeError(f".from_bernstein_basis only accepts BPoly instances. Got "
                            f"{type(bp)} instead.")

        b = np.asarray(bp.c)
        x = np.asarray(bp.x, dtype=np.float64)
        k = b.shape[0] - 1
        h = np.diff(x).reshape((-1,) + (1,) * (b.ndim - 2))
        c = np.zeros_like(b, dtype=np.result_type(b, np.float64))
        for d in range(k + 1):
            for a in range(d + 1):
                c[k - d] += b[a] * math.comb(k, a) * math.comb(k - a, d - a) * (-1) ** (d - a)
            c[k - d] /= h ** d
        if extrapolate is None:
            extrapolate = bp.extrapolate
        return cls.construct_fast(c, x, extrapolate, bp.axis)

    def _values(self, c: np.ndarray, flat: np.ndarray, nu: int) -> np.ndarray:
        """Derivative nu at flat: natively for real c and increasing breakpoints, else by
        Horner's rule in NumPy (complex c, descending breakpoints): (len, columns)."""
        if self.x[0] <= self.x[-1] and not np.iscomplexobj(c):
            return _native.evaluate_pieces(_f64(self.x), _f64(c), _f64(flat), nu)
        for _ in range(nu):
            c = c[:-1] * np.arange(c.shape[0] - 1, 0, -1)[:, None, None]
        i = np.clip(self._piece_of(flat), 0, c.shape[1] - 1)
        dx = (flat - self.x[i])[:, None]
        out = np.zeros((len(flat), c.shape[2]), dtype=np.result_type(c, np.float64))
        for m in range(c.shape[0]):
            out = out * dx + c[m, i]
        return out

    def derivative(self, nu: int = 1) -> PPoly:
        """The nu-th derivative as a PPoly (nu < 0: the antiderivative)."""
        if nu < 0:
            return self.antiderivative(-nu)
        c = self.c
        for _ in range(nu):
            shape = (c.shape[0] - 1,) + (1,) * (c.ndim - 1)
            c = c[:-1] * np.arange(c.shape[0] - 1, 0, -1).reshape(shape)
        if c.shape[0] == 0:
            c = np.zeros((1, *self.c.shape[1:]), dtype=self.c.dtype)
        return self._like(c, self.x, self.extrapolate)

    def antiderivative(self, nu: int = 1) -> PPoly:
        """The nu-th antiderivative (zero at x[0], continuous with its nu - 1 derivatives) as
        a PPoly of degree k - 1 + nu; a periodic extrapolation becomes False, as SciPy's.
        One order at a time, natively: term m (power p) becomes c_m / (p + 1) of power p + 1,
        and each piece's new constant is the integral of the pieces before it."""
        if nu <= 0:
            return self.derivative(-nu)
        c = self._column_c()
        x = _f64(self.x)
        for _ in range(nu):
            if np.iscomplexobj(c):
                c = (_native.antiderivative_pieces(x, _f64(c.real))
                     + 1j * _native.antiderivative_pieces(x, _f64(c.imag)))
            else:
                c = _native.antiderivative_pieces(x, _f64(c))
        c = c.reshape(c.shape[:2] + self.c.shape[2:])
        extrapolate = False if self.extrapolate == "periodic" else self.extrapolate
        return self._like(c, self.x, extrapolate)

    def integrate(self, a, b, extrapolate=None) -> np.ndarray:
        """The integral from a to b (b < a: its negative), shape c.shape[2:], as SciPy's:
        `extrapolate` None (the polynomial's), True (the end pieces past the breakpoints),
        False (NaN when a or b lies outside them) or "periodic" (whole periods and the rest,
        wrapped); see `integrals`."""
        mode = self.extrapolate if extrapolate is None else _extrapolate(extrapolate)
        a, b = float(a), float(b)
        if mode is not True or self.x[0] > self.x[-1] or a != a or b != b:
            return self._integrated(a, b, mode)
        # The common call, in the pieces it touches only (natively; a complex c as its real
        # and imaginary parts).
        c = self._column_c()
        out = _native.integrate_pieces(_f64(self.x), _f64(c.real), a, b)
        if np.iscomplexobj(c):
            out = out + 1j * _native.integrate_pieces(_f64(self.x), _f64(c.imag), a, b)
        return out.reshape(self.c.shape[2:])

    def _integrated(self, a: float, b: float, mode) -> np.ndarray:
        """`integrate` in every mode, through `integrals`."""
        m = self.c.shape[1]
        c, x = self._ascending()
        total = integrals(c, x[:-1], x[1:], np.array([0, m]), np.array([a]), np.array([b]),
                           mode)
        return total[0].reshape(self.c.shape[2:])

    def _ascending(self):
        """(c (k, m, columns), x) with x increasing: a descending polynomial's pieces in
        reverse order, each re-expanded at its left end x_{i+1}: with h = x_i - x_{i+1},
        (v - h)^p = sum_j C(p, j) v^j (-h)^(p - j)."""
        c = self._column_c()
        if self.x[0] <= self.x[-1]:
            return c, self.x

        k = c.shape[0]
        h = (self.x[:-1] - self.x[1:])[:, None]
        shifted = np.zeros_like(c)
        for p in range(k):
            for j in range(p + 1):
                shifted[k - 1 - j] += c[k - 1 - p] * math.comb(p, j) * (-h) ** (p - j)
        return shifted[:, ::-1], self.x[::-1].copy()

    def solve(self, y=0.0, discontinuity: bool = True, extrapolate=None):
        """The x where the polynomial equals y, as SciPy finds them: per piece the real roots
        of its polynomial minus y (companion-matrix eigenvalues from degree 3, closed forms
        below), refined by one Newton step, kept inside the piece (the first and last pieces
        half-open outward when extrapolating; "periodic" extrapolates, as SciPy's), a
        repeated value once; a piece equal to y everywhere gives its start and NaN; with
        `discontinuity`, a breakpoint where the value jumps across y. One array for a 1-D
        polynomial, else an object array of them, shape c.shape[2:]."""
        if np.iscomplexobj(self.c):
            raise ValueError("Root finding is only for real-valued polynomials")
        mode = self.extrapolate if extrapolate is None else _extrapolate(extrapolate)
        y = float(y)
        c, x = self._ascending()
        found = [_real_roots(c[:, :, j], x, y, bool(discontinuity), bool(mode),
                             not self._fitted)
                 for j in range(c.shape[2])]
        if self.c.ndim == 2:
            return found[0]
        out = np.empty(len(found), dtype=object)
        for j, roots in enumerate(found):
            out[j] = roots
        return out.reshape(self.c.shape[2:])

    def roots(self, discontinuity: bool = True, extrapolate=None):
        """`solve(0, ...)`."""
        return self.solve(0.0, discontinuity, extrapolate)


def _candidates(c: np.ndarray, y: float, widths: np.ndarray, exact: bool):
    """Every piece's complex roots of its polynomial minus y, for all pieces at once: (piece,
    real part, imaginary part) arrays, each piece's sorted by real part, and the pieces equal
    to y everywhere. A piece's degree is that of its highest nonzero term where `exact`
    (SciPy's rule, for coefficients given as they are), else of its highest term that is not
    negligible:
    nonzero, and larger over the piece's width than 8 eps of all its terms there (a fitted
    spline's coefficients carry the fit's rounding where SciPy's are exact zeros: a line's
    cubic term of 1e-20 would put a root at 1e8). From degree 3 the roots are the eigenvalues
    of the companion matrix (last column -a_j / a_lead), below it the closed forms, the
    quadratic's without cancellation (the closed forms of cubics are the native finder's, which
    takes every polynomial of degree 3 and below)."""
    k = c.shape[0]
    powers = np.arange(k - 1, -1, -1)[:, None]
    size = np.abs(c) * np.abs(widths)[None, :] ** powers
    nonzero = (c != 0) & (exact | (size > 8 * np.finfo(float).eps * size.sum(axis=0)))
    lead = np.where(nonzero.any(axis=0), nonzero.argmax(axis=0), k)
    order = k - 1 - lead
    constant = c[-1] - y
    flat = (order < 0) | (order == 0)
    everywhere = np.flatnonzero(flat & np.where(order < 0, y == 0, constant == 0))
    groups: list = []
    for n in np.unique(order[order >= 1]):
        idx = np.flatnonzero(order == n)
        a = c[k - 1 - n:, idx].T.copy()  # (pieces, n + 1), highest power first
        a[:, -1] -= y
        if n == 1:
            wr, wi = (-a[:, 1] / a[:, 0])[:, None], np.zeros((len(idx), 1))
        elif n == 2:
            wr, wi = _quadratic(a)
        else:
            wr, wi = _eigenvalues(a)
        groups.append((np.repeat(idx, n), wr.ravel(), wi.ravel()))
    if not groups:
        return np.array([], int), np.array([]), np.array([]), everywhere
    pieces, real, imag = (np.concatenate(parts) for parts in zip(*groups))
    order_of = np.argsort(pieces, kind="stable")
    return pieces[order_of], real[order_of], imag[order_of], everywhere


def _eigenvalues(a: np.ndarray):
    """The roots of the polynomials in the rows of `a` (highest power first, degree >= 3) as
    the eigenvalues of their companion matrices (last column -a_j / a_lead), each row's
    sorted by real part: as SciPy finds them."""
    rows, n = a.shape[0], a.shape[1] - 1
    companion = np.zeros((rows, n, n))
    companion[:, np.arange(1, n), np.arange(n - 1)] = 1.0
    companion[:, :, -1] = -a[:, :0:-1] / a[:, :1]
    w = np.linalg.eigvals(companion) if rows else np.zeros((0, n), complex)
    w = np.take_along_axis(w, np.argsort(w.real, axis=1, kind="stable"), axis=1)
    return w.real, w.imag


def _quadratic(a: np.ndarray):
    """The roots of a0 u^2 + a1 u + a2 for rows of `a`: a complex pair where the discriminant
    is negative, else the larger root by the formula and the other from the product."""
    a0, a1, a2 = a[:, 0], a[:, 1], a[:, 2]
    d = a1 * a1 - 4 * a0 * a2
    root = np.sqrt(np.abs(d))
    with np.errstate(divide="ignore", invalid="ignore"):
        first = np.where(a1 < 0, (2 * a2) / (-a1 + root), (-a1 - root) / (2 * a0))
        second = np.where(a1 < 0, (-a1 + root) / (2 * a0), (2 * a2) / (-a1 - root))
    double = d == 0
    first = np.where(double, -a1 / (2 * a0), first)
    second = np.where(double, -a1 / (2 * a0), second)
    complex_pair = d < 0
    wr = np.where(complex_pair[:, None], (-a1 / (2 * a0))[:, None],
                  np.stack([first, second], axis=1))
    wi = np.where(complex_pair[:, None],
                  np.stack([-root / (2 * a0), root / (2 * a0)], axis=1), 0.0)
    return wr, wi


def _values(c: np.ndarray, pieces: np.ndarray, s: np.ndarray, d: int) -> np.ndarray:
    """Derivative d (0 or 1) of pieces `pieces` at local s, all at once."""
    k = c.shape[0]
    out = np.zeros(len(s))
    for m in range(k - d):
        p = k - 1 - m
        out = out * s + c[m, pieces] * (p if d else 1)
    return out


def _real_roots(c: np.ndarray, x: np.ndarray, y: float, discontinuity: bool,
                extrapolate: bool, exact: bool) -> np.ndarray:
    """The roots of one column's pieces c (k, m) minus y (see `PPoly.solve`)."""
    m = c.shape[1]
    return _roots(c, x[:-1], x[1:], np.array([0, m]), y, discontinuity, extrapolate, exact)[0]


def _roots(c: np.ndarray, start: np.ndarray, end: np.ndarray, offsets: np.ndarray, y: float,
           discontinuity: bool, extrapolate: bool, exact: bool = False):
    """The roots minus y of many splines at once: spline s's pieces are columns
    offsets[s]:offsets[s+1] of c (k, P), piece p spanning [start[p], end[p]]; returns (roots,
    offsets of each spline's roots), as SciPy finds them (see `PPoly.solve`). Cubics and below
    go to the native finder (python/src/roots.rs), which leaves the pieces whose closed form
    may decide real against complex otherwise than the companion matrix (a nearly double root)
    to NumPy's eigenvalues here; higher degrees to `_roots_numpy`. `exact`: SciPy's degree
    rule (the highest nonzero term) rather than the fits' (see `_candidates`)."""
    k = c.shape[0]
    if k > 4:
        return _roots_numpy(c, start, end, offsets, y, discontinuity, extrapolate, exact)
    cubic = np.zeros((4, c.shape[1]))
    cubic[4 - k:] = c
    return solved(_native.solve_pieces(cubic, np.ascontiguousarray(start, np.float64),
                                        np.ascontiguousarray(end, np.float64),
                                        np.asarray(offsets, np.int64), y, discontinuity,
                                        extrapolate, exact), y)


def solved(pending, y: float):
    """A native solve's second step: the real eigenvalues of the pieces it left undecided
    (their companion matrices minus y, each piece's ascending), handed back to `finish` ->
    (roots, offsets)."""
    which, a = pending.undecided()
    a[:, -1] -= y
    wr, wi = _eigenvalues(a)
    real = wi == 0
    return pending.finish(np.repeat(which, 3)[real.ravel()], wr[real])


def _roots_numpy(c: np.ndarray, start: np.ndarray, end: np.ndarray, offsets: np.ndarray,
                 y: float, discontinuity: bool, extrapolate: bool, exact: bool):
    """`_roots` in NumPy, for any degree: every piece's candidates are found together, then
    put in SciPy's order (per spline and piece: a breakpoint where the value jumps across y,
    then the piece's roots by real part), a value dropped where it equals the one before it,
    and a piece equal to y everywhere gives its start and NaN."""
    pieces_of = np.diff(offsets)
    spline = np.repeat(np.arange(len(pieces_of)), pieces_of)
    first = np.zeros(c.shape[1], bool)
    last = np.zeros(c.shape[1], bool)
    first[offsets[:-1][pieces_of > 0]] = True
    last[offsets[1:][pieces_of > 0] - 1] = True
    pieces, real, imag, everywhere = _candidates(c, y, end - start, exact)
    keep = imag == 0
    pieces, real = pieces[keep], real[keep]
    # One Newton step where it moves the root by less than the root's own size.
    f = _values(c, pieces, real, 0) - y
    df = _values(c, pieces, real, 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        step = np.where(df != 0, f / df, 0.0)
    real = np.where((df != 0) & (np.abs(step) < np.abs(real)), real - step, real)
    roots = real + start[pieces]
    inside = (start[pieces] <= roots) & (roots <= end[pieces])
    if extrapolate:
        # The first piece open to the left, the last open to the right (one piece: both).
        open_left = first[pieces] & (roots <= end[pieces])
        open_right = last[pieces] & (roots >= start[pieces])
        inside = np.where(first[pieces] & last[pieces], True, inside | open_left | open_right)
    pieces, roots = pieces[inside], roots[inside]
    # Events: (piece, rank, value, whole): rank 0 a jump at the piece's start, 1 a root, 2
    # the piece equal to y everywhere (its start, then NaN).
    event_piece = [pieces, everywhere, everywhere]
    event_rank = [np.ones(len(pieces)), np.full(len(everywhere), 2), np.full(len(everywhere), 3)]
    event_value = [roots, start[everywhere], np.full(len(everywhere), np.nan)]
    if discontinuity:
        inner = np.flatnonzero(~first)
        before = _values(c, inner - 1, end[inner - 1] - start[inner - 1], 0) - y
        after = c[-1, inner] - y
        jumps = inner[((before < 0) & (after > 0)) | ((before > 0) & (after < 0))]
        event_piece.append(jumps)
        event_rank.append(np.zeros(len(jumps)))
        event_value.append(start[jumps])
    piece = np.concatenate(event_piece).astype(np.int64)
    rank = np.concatenate(event_rank)
    value = np.concatenate(event_value)
    order = np.lexsort((rank, piece))
    piece, rank, value = piece[order], rank[order], value[order]
    owner = spline[piece]
    # A value equal to the one kept before it in its spline is dropped (the zero pieces'
    # start and NaN are always kept, and the NaN makes the next value new).
    new = np.ones(len(value), bool)
    new[1:] = (owner[1:] != owner[:-1]) | (value[1:] != value[:-1])
    new |= rank >= 2
    value, owner = value[new], owner[new]
    counts = np.bincount(owner, minlength=len(pieces_of))
    return value, np.concatenate([[0], np.cumsum(counts)])


def _located(start: np.ndarray, offsets: np.ndarray, x: np.ndarray) -> np.ndarray:
    """For each spline s and its x[s], the last of its pieces offsets[s]:offsets[s+1] that
    starts at or below x[s] (its first piece below it, and at NaN): a binary search of all
    splines at once."""
    if len(offsets) == 2:
        # One spline: NumPy's own search.
        first, count = offsets[0], offsets[1] - offsets[0]
        found = np.searchsorted(start[first:offsets[1]], x, side="right") - 1
        return first + np.where(np.isnan(x), 0, np.clip(found, 0, count - 1))
    lo, hi = offsets[:-1].copy(), offsets[1:] - 1
    while np.any(lo < hi):
        middle = (lo + hi + 1) // 2
        below = start[np.minimum(middle, hi)] <= x
        lo, hi = np.where(below & (lo < hi), middle, lo), np.where(below | (lo >= hi), hi,
                                                                   middle - 1)
    return lo


def integrals(c: np.ndarray, start: np.ndarray, end: np.ndarray, offsets: np.ndarray,
               a: np.ndarray, b: np.ndarray, mode) -> np.ndarray:
    """The integral of each spline from a[s] to b[s] (S,), all splines at once: spline s's
    pieces are columns offsets[s]:offsets[s+1] of c (k, P, m), piece p spanning
    [start[p], end[p]]; returns (S, m).

    With P_p(v) = sum_m c[m, p] v^(k-m) / (k - m) the integral of piece p from its start to
    v, the integral from a to b (a <= b, in pieces pa <= pb) is
        P_pb(b - start_pb) - P_pa(a - start_pa) + sum_{pa <= p < pb} P_p(end_p - start_p),
    the end pieces continuing past the knots. b < a gives the negative; `mode` False: NaN
    where a or b lies outside the knots; "periodic": b - a as whole periods of the spline's
    integral and a rest from a wrapped into the knots, itself wrapped at the end."""
    k = c.shape[0]

    def partial(p, v):
        # Horner: ((c_0 / k) v + c_1 / (k - 1)) v + ... + c_{k-1}, times v.
        v = v[:, None]
        total = c[0, p] / k
        for m in range(1, k):
            total = total * v + c[m, p] / (k - m)
        return total * v

    full = partial(slice(None), end - start)

    def within(a, b):
        pa, pb = _located(start, offsets, a), _located(start, offsets, b)
        # Whole pieces pa..pb-1 of each spline (reduceat's pairs; an empty range gives 0).
        pairs = np.clip(np.stack([pa, pb], axis=1).ravel(), 0, max(c.shape[1] - 1, 0))
        whole = np.add.reduceat(full, pairs, axis=0)[0::2] if c.shape[1] else full[:0]
        whole[pa >= pb] = 0
        return partial(pb, b - start[pb]) - partial(pa, a - start[pa]) + whole

    sign = np.where(b < a, -1.0, 1.0)[:, None]
    a, b = np.minimum(a, b), np.maximum(a, b)
    lo, hi = start[offsets[:-1]], end[offsets[1:] - 1]
    if mode == "periodic":
        period = hi - lo
        periods, rest = np.divmod(b - a, period)
        a = lo + np.mod(a - lo, period)
        wraps = a + rest > hi
        total = periods[:, None] * within(lo, hi)
        total += np.where(wraps[:, None], within(a, hi) + within(lo, lo + rest + a - hi),
                          within(a, np.minimum(a + rest, hi)))
    else:
        total = within(a, b)
        if mode is False:
            total[(a < lo) | (b > hi)] = np.nan
    return sign * total
