"""Tensor-product B-splines (SciPy's `NdBSpline`) and their interpolating fit on a grid.

    s(x) = sum_{i_0..i_{d-1}} c[i_0, .., i_{d-1}] prod_a B_{i_a, k_a}(x_a; t_a)

is evaluated in the extension (`_native.evaluate_tensor`: the k_a + 1 B-splines of each axis'
knot span by de Boor's recurrence, contracted one axis at a time, on every thread).

The interpolating fit through values on a grid (`fit_grid`, what RegularGridInterpolator's
spline methods build) is separable: the collocation matrix of the whole grid is the Kronecker
product A_0 x A_1 x .. of each axis' 1-D collocation matrix on SciPy's not-a-knot knots, so
c = (A_0^-1 x A_1^-1 x ..) y is d sweeps of 1-D banded solves, one axis at a time, every line
of the grid along that axis a right-hand side of one elimination (O(N k^2) for N values, in
float64, exact up to rounding). SciPy 1.13+ assembles the sparse N x N system instead and
solves it iteratively (`gcrotmk`, atol 1e-6); the interpolant is the same one, without the
iteration's error.
"""

from __future__ import annotations

import operator
from math import prod

import numpy as np

from . import _bspl, _collocation, _native


def _value_dtype(dtype) -> type:
    return np.complex128 if np.issubdtype(dtype, np.complexfloating) else np.float64


def _knots_and_degrees(t, k) -> tuple:
    """SciPy's checks of `t` (a tuple of knot vectors) and `k` (one degree, or one per axis),
    each a ValueError naming the axis; the knots as float64 arrays and the degrees."""
    if not isinstance(t, tuple):
        raise ValueError(f"Expect `t` to be a tuple of array-likes. Got {t} instead.")
    d = len(t)
    if np.ndim(k) == 0:
        k = (k,) * d
    k = tuple(operator.index(kd) for kd in k)
    if len(k) != d:
        raise ValueError(f"len(t) = {d} != {len(k) = }.")
    knots = []
    for a, (ta, ka) in enumerate(zip(t, k)):
        ta = np.asarray(ta, dtype=np.float64)
        if ka < 0:
            raise ValueError(f"Spline degree in dimension {a} cannot be negative.")
        if ta.ndim != 1:
            raise ValueError(f"Knot vector in dimension {a} must be one-dimensional.")
        n = len(ta) - ka - 1
        if n < ka + 1:
            raise ValueError(f"Need at least {2 * ka + 2} knots for degree {ka} in "
                             f"dimension {a}.")
        if (np.diff(ta) < 0).any():
            raise ValueError(f"Knots in dimension {a} must be in a non-decreasing order.")
        if len(np.unique(ta[ka:n + 1])) < 2:
            raise ValueError(f"Need at least two internal knots in dimension {a}.")
        if not np.isfinite(ta).all():
            raise ValueError(f"Knots in dimension {a} should not have nans or infs.")
        knots.append(np.ascontiguousarray(ta))
    return tuple(knots), k


def derivative_orders(nu, d: int) -> list:
    if nu is None:
        return [0] * d
    orders = np.asarray(nu)
    if orders.ndim != 1 or orders.shape[0] != d:
        raise ValueError(f"invalid number of derivative orders {nu = } for ndim = {d}.")
    orders = orders.astype(np.int64)
    if (orders < 0).any():
        raise ValueError(f"derivatives must be positive, got {nu = }")
    return [int(o) for o in orders]


class NdBSpline:
    """SciPy's `NdBSpline(t, c, k, extrapolate=None)`: the tensor product of d B-spline bases,
    t a tuple of d knot vectors, c of shape (n_0, .., n_{d-1}, ...) (trailing axes: values per
    point), k one degree or one per axis. Evaluated in float64 on the CPU's threads (any d, any
    k), or, on a GPU `context`, a bicubic one (d = 2, k = 3, real, up to 64 values a point) at
    points inside its base intervals, derivatives of total order <= 2, as the crate's NURBS
    surface without weights on the device: float32 within the contract's surface promise.
    """

    def __init__(self, t, c, k, *, extrapolate=None, context=None):
        self._t, self._k = _knots_and_degrees(t, k)
        self.extrapolate = True if extrapolate is None else bool(extrapolate)
        self.context = context
        c = np.asarray(c)
        d = len(self._t)
        if c.ndim < d:
            raise ValueError(f"Coefficients must be at least {d}-dimensional.")
        for a in range(d):
            n = len(self._t[a]) - self._k[a] - 1
            if c.shape[a] != n:
                raise ValueError(f"Knots, coefficients and degree in dimension {a} are "
                                 f"inconsistent: got {c.shape[a]} coefficients for "
                                 f"{len(self._t[a])} knots, need at least {n} for k={k}.")
        self._c = np.ascontiguousarray(c, dtype=_value_dtype(c.dtype))
        self._flat = None

    @classmethod
    def _made(cls, t: tuple, c: np.ndarray, k: tuple, context=None) -> NdBSpline:
        """A spline whose knots this package made (a fit's, a grid's): not checked again."""
        self = cls.__new__(cls)
        self._t, self._k, self._c = t, k, np.ascontiguousarray(c, dtype=_value_dtype(c.dtype))
        self.extrapolate, self.context, self._flat = True, context, None
        return self

    @property
    def t(self) -> tuple:
        return self._t

    @property
    def k(self) -> tuple:
        return self._k

    @property
    def c(self) -> np.ndarray:
        return self._c

    def _columns(self) -> np.ndarray:
        """c as the extension takes it: (n_0 · .. · n_{d-1}, m) float64 (a complex value as
        its real and imaginary parts), made once."""
        if self._flat is None:
            d = len(self._t)
            c = self._c
            if c.dtype.kind == "c":
                c = c.reshape((*c.shape[:d], -1)).view(np.float64)
            self._flat = np.require(c.reshape(prod(c.shape[:d]), -1), np.float64, ["C", "A"])
        return self._flat

    def __call__(self, xi, *, nu=None, extrapolate=None) -> np.ndarray:
        """Derivative `nu` (one order per axis; None: the values) at the points xi (..., d):
        shape xi.shape[:-1] + c.shape[d:]. Past the base interval of an axis its end
        polynomials continue where `extrapolate` (default: the spline's), else NaN."""
        d = len(self._t)
        extrapolate = self.extrapolate if extrapolate is None else bool(extrapolate)
        orders = derivative_orders(nu, d)
        xi = np.asarray(xi, dtype=np.float64)
        shape = xi.shape
        if shape[-1] != d:
            raise ValueError(f"Shapes: xi.shape={shape} and ndim={d}")
        points = np.require(xi.reshape(-1, d), np.float64, ["C", "A"])
        on_gpu = on_device([self], [points], orders)
        if on_gpu is not None:
            return on_gpu[0].reshape(shape[:-1] + self._c.shape[d:])
        out = _native.evaluate_tensor(list(self._t), list(self._k), self._columns(), points,
                                      orders, extrapolate)
        if self._c.dtype.kind == "c":
            out = np.ascontiguousarray(out).view(np.complex128)
        return out.reshape(shape[:-1] + self._c.shape[d:])

    @classmethod
    def design_matrix(cls, xvals, t, k, extrapolate=True):
        """SciPy's design matrix: a `scipy.sparse.csr_array` with a row per point of xvals
        (N, d), the products of the axes' B-splines that do not vanish there, in C order of
        the coefficients."""
        from scipy.sparse import csr_array

        xvals = np.asarray(xvals, dtype=np.float64)
        if xvals.ndim != 2:
            raise ValueError(f"xvals: the points must be a 2-D array (N, d), got shape "
                             f"{xvals.shape}")
        d = xvals.shape[-1]
        if len(t) != d:
            raise ValueError(f"Data and knots are inconsistent: len(t) = {len(t)} for "
                             f" {d = }.")
        t, k = _knots_and_degrees(tuple(t), k)
        counts = [len(ta) - ka - 1 for ta, ka in zip(t, k)]
        data = np.ones((len(xvals), 1))
        columns = np.zeros((len(xvals), 1), dtype=np.int64)
        for a in range(d):
            x = xvals[:, a]
            if not extrapolate and x.size and (x.min() < t[a][k[a]] or x.max() > t[a][-k[a] - 1]):
                raise ValueError(f"Out of bounds in dimension {a} with x = {x}.")
            span = _bspl.intervals(t[a], k[a], x)
            values = _bspl.basis(t[a], k[a], x, span)
            index = (span - k[a])[:, None] + np.arange(k[a] + 1)[None, :]
            data = (data[:, :, None] * values[:, None, :]).reshape(len(xvals), -1)
            columns = (columns[:, :, None] * counts[a] + index[:, None, :]).reshape(
                len(xvals), -1)
        width = data.shape[1]
        indptr = np.arange(0, len(xvals) * width + 1, width, dtype=np.int64)
        return csr_array((data.ravel(), columns.ravel(), indptr),
                         shape=(len(xvals), prod(counts)))

    def derivative(self, nu) -> NdBSpline:
        """The partial derivative of orders nu (one per axis) as an NdBSpline: each axis'
        B-spline derivative (knots one fewer at each end per order, degree k - nu; a zero
        spline of degree 0 where nu > k)."""
        d = len(self._t)
        orders = np.asarray(nu)
        if orders.ndim != 1 or orders.shape[0] != d:
            raise ValueError(f"invalid number of derivative orders {nu = } for ndim = {d}.")
        if (orders < 0).any():
            raise ValueError(f"derivative orders must be positive, got {nu = }")
        t, k, c = list(self._t), list(self._k), self._c
        for a, order in enumerate(int(o) for o in orders):
            if order == 0:
                continue
            moved = np.moveaxis(c, a, 0)
            if order > k[a]:
                # SciPy's zero spline: degree 0 on the same knots.
                k[a] = 0
                moved = np.zeros((len(t[a]) - 1, *moved.shape[1:]), dtype=c.dtype)
            else:
                flat = moved.reshape(moved.shape[0], -1)
                t[a], flat, k[a] = _bspl.derivative(t[a], flat, k[a], order)
                moved = flat[:len(t[a]) - k[a] - 1].reshape((-1, *moved.shape[1:]))
            c = np.moveaxis(moved, 0, a)
        return NdBSpline(tuple(t), c, tuple(k), extrapolate=self.extrapolate,
                         context=self.context)

    def __reduce__(self):
        return (restore, (self._t, self._c, self._k, self.extrapolate, self.context))


# The surface planes of each derivative order (nu_u, nu_v) a surface gives, and the
# `derivatives` that makes it.
_PLANES = {(0, 0): ("points", 0), (1, 0): ("du", 1), (0, 1): ("dv", 1), (2, 0): ("duu", 2),
           (1, 1): ("duv", 2), (0, 2): ("dvv", 2)}


def on_device(splines: list, points: list, orders: list):
    """Bicubic splines on a GPU context, each at its points (N_i, 2) in one dispatch (the
    crate's NURBS surfaces without weights at those (u, v)): their values (N_i, m) float32, or
    None where the call is not one the device takes (another context, degree or dimension,
    complex or wide values, a derivative order it has no plane for, a point outside a base
    interval or NaN, knots the crate's NURBS rules refuse): the CPU evaluates those."""
    context = splines[0].context
    plane = _PLANES.get(tuple(orders))
    if context is None or context.backend != "gpu" or plane is None:
        return None
    for spline, xi in zip(splines, points):
        c = spline.c
        if len(spline.t) != 2 or spline.k != (3, 3) or c.dtype.kind == "c" or \
                spline.context is not context or not 1 <= spline._columns().shape[1] <= 64 or \
                not all(_bspl.cubic_knots_taken(t) for t in spline.t):
            return None
        for a, t in enumerate(spline.t):
            x = xi[:, a]
            if len(x) and not (t[3] <= x.min() and x.max() <= t[-4]):
                return None  # also NaN
    nets = [s._columns().reshape(len(s.t[0]) - 4, len(s.t[1]) - 4, -1) for s in splines]
    result = context.tessellate_surfaces(
        nets, "nurbs", knots_u=[s.t[0] for s in splines], knots_v=[s.t[1] for s in splines],
        at=list(points), derivatives=plane[1])
    values = getattr(result, plane[0])
    return np.split(values, result.surface_offsets[1:-1])


def restore(t, c, k, extrapolate, context) -> NdBSpline:
    return NdBSpline(t, c, k, extrapolate=extrapolate, context=context)


def fit_grid(grid: tuple, values: np.ndarray, k: tuple) -> tuple:
    """The knots (SciPy's not-a-knot knots of each axis) and the coefficients of the tensor
    B-spline of degrees k through `values` (n_0, .., n_{d-1}, ...) on the grid (d strictly
    increasing axes), by one sweep of banded solves per axis (see the module's documentation).
    Complex values are fitted as their real and imaginary parts."""
    grid = tuple(np.asarray(x, dtype=np.float64) for x in grid)
    t = tuple(_collocation.not_a_knot(x, ka) for x, ka in zip(grid, k))
    return t, solve_grid(grid, t, k, values)


def solve_grid(grid: tuple, t: tuple, k: tuple, values: np.ndarray) -> np.ndarray:
    """The coefficients on knots t (one vector per axis, len(t_a) = len(grid_a) + k_a + 1) of
    the tensor B-spline of degrees k through `values` at the grid's nodes, in the extension
    (`_native.fit_tensor`); LinAlgError where an axis' collocation matrix is singular."""
    d = len(grid)
    dtype = _value_dtype(values.dtype)
    c: np.ndarray = np.ascontiguousarray(values, dtype=dtype)
    shape = c.shape
    real = c.reshape(int(np.prod(shape[:d])), -1)
    if dtype is np.complex128:
        real = real.view(np.float64)
    solved = _native.fit_tensor([np.require(x, np.float64, ["C", "A"]) for x in grid],
                                [np.require(ta, np.float64, ["C", "A"]) for ta in t],
                                [int(ka) for ka in k], np.require(real, np.float64, ["C", "A"]))
    if solved is None:
        raise _collocation.singular()
    if dtype is np.complex128:
        solved = solved.view(np.complex128)
    return solved.reshape(shape)
