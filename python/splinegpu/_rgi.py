"""SciPy's `RegularGridInterpolator` and `interpn`: interpolation of values on a rectilinear grid
(each axis strictly ascending or descending, spacing free) at scattered points.

Methods, as SciPy 1.17 defines them:
- "linear": multilinear on each grid cell; "slinear": the same function, as a tensor B-spline of
  degree 1 (SciPy builds it by a sparse solve; both are evaluated here by the extension's
  tensor-product evaluator, the identity being the degree-1 collocation);
- "cubic", "quintic": the tensor-product not-a-knot B-spline of degree 3 or 5 through the
  values, fitted by separable banded solves along each axis (`_ndbspline.fit_grid`); the
  "_legacy" variants (SciPy: 1-D fits folded axis by axis at each point) are the same
  interpolant and take the same path;
- "pchip": PCHIP folded axis by axis, the last axis first (`_native.pchip_grid`);
- "nearest": the nearest grid node per axis, half-way rounding down.
Points past the grid raise, or get `fill_value`, or (fill_value None) the method's
extrapolation; a NaN coordinate gives NaN.
"""

from __future__ import annotations

import inspect
import itertools

import numpy as np

from . import _collocation, _native
from ._fitpack2 import RectBivariateSpline
from ._ndbspline import NdBSpline, fit_grid

_DEGREES = {"slinear": 1, "cubic": 3, "quintic": 5, "pchip": 3,
            "slinear_legacy": 1, "cubic_legacy": 3, "quintic_legacy": 5}
_SPLINES = {"slinear", "cubic", "quintic"}
_METHODS = ["linear", "nearest", *_DEGREES]


def _axes(points) -> tuple:
    """The axes as ascending float64 arrays, and the axes that were given descending."""
    grid, descending = [], []
    for a, p in enumerate(points):
        p = np.asarray(p, dtype=np.float64)
        if not np.all(p[1:] > p[:-1]):
            if np.all(p[1:] < p[:-1]):
                descending.append(a)
                p = p[::-1]
            else:
                raise ValueError(f"The points in dimension {a} must be strictly ascending or "
                                 f"descending")
        grid.append(np.ascontiguousarray(p))
    return tuple(grid), tuple(descending)


def _check_shape(grid: tuple, values) -> None:
    if len(grid) > values.ndim:
        raise ValueError(f"There are {len(grid)} point arrays, but values has {values.ndim} "
                         f"dimensions")
    for a, p in enumerate(grid):
        if p.ndim != 1:
            raise ValueError(f"The points in dimension {a} must be 1-dimensional")
        if values.shape[a] != len(p):
            raise ValueError(f"There are {len(p)} points and {values.shape[a]} values in "
                             f"dimension {a}")


def coordinates(xi, ndim: int) -> np.ndarray:
    """Points as SciPy takes them: an array (..., ndim) (a 1-D array is rows of ndim), or a
    tuple of ndim coordinate arrays that broadcast together."""
    if isinstance(xi, tuple) and len(xi) == 1:
        xi = xi[0]
    if isinstance(xi, tuple):
        parts = np.broadcast_arrays(*xi)
        if any(p.shape != parts[0].shape for p in parts):
            raise ValueError("coordinate arrays do not have the same shape")
        return np.stack([np.asarray(p, dtype=np.float64) for p in parts], axis=-1)
    xi = np.asanyarray(xi)
    return xi.reshape(-1, ndim) if xi.ndim == 1 else xi


def _spline_points(grid: tuple, method: str) -> None:
    k = _DEGREES[method]
    for a, p in enumerate(grid):
        n = len(np.atleast_1d(p))
        if n <= k:
            raise ValueError(f"There are {n} points in dimension {a}, but method {method} "
                             f"requires at least  {k + 1} points per dimension.")


class RegularGridInterpolator:
    """SciPy's `RegularGridInterpolator(points, values, method="linear", bounds_error=True,
    fill_value=nan, *, solver=None, solver_args=None)` (see the module's documentation for the
    methods). The spline methods are fitted exactly by separable solves; a `solver` given is
    SciPy's alternative (the global sparse system handed to it) and is honoured as asked. On a
    GPU `context`, "cubic" on 2-D grids is evaluated on the device where NdBSpline's rules
    allow (float32); every other method and dimension in float64 on the CPU.
    """

    _ALL_METHODS = _METHODS

    def __init__(self, points, values, method="linear", bounds_error=True,
                 fill_value=np.nan, *, solver=None, solver_args=None, context=None):
        if method not in _METHODS:
            raise ValueError(f"Method '{method}' is not defined")
        if method in _DEGREES:
            _spline_points(points, method)
        self.method = method
        self.context = context
        self.bounds_error = bounds_error
        self._grid, self._descending = _axes(points)
        self._values = self._checked_values(values)
        _check_shape(self._grid, self._values)
        self.fill_value = self._checked_fill(fill_value)
        if self._descending:
            self._values = np.flip(self._values, axis=self._descending)
        if method == "pchip" and np.iscomplexobj(self._values):
            raise ValueError("`PchipInterpolator` only works with real values. If you are "
                             "trying to use the real components of the passed array, use "
                             "`np.real` on the array before passing to "
                             "`RegularGridInterpolator`.")
        if method not in _SPLINES and (solver is not None or solver_args):
            raise ValueError(f"{method =} does not accept the 'solver' argument. Got "
                             f" {solver = } and with arguments {solver_args}.")
        self._spline = None
        if method in _DEGREES and method != "pchip":
            # SciPy builds the legacy methods at each call, where it refuses values that are
            # not finite: those wait for the call (`_tensor`) to be refused.
            legacy = method.endswith("_legacy")
            if not legacy or np.isfinite(np.asarray(self._values)).all():
                self._spline = self._fit(method, solver, solver_args or {})

    @staticmethod
    def _checked_values(values):
        if not hasattr(values, "ndim"):
            values = np.asarray(values)
        if hasattr(values, "dtype") and not np.issubdtype(values.dtype, np.inexact):
            values = values.astype(float)
        return values

    def _checked_fill(self, fill_value):
        if fill_value is not None:
            kind = np.asarray(fill_value).dtype
            if hasattr(self._values, "dtype") and not np.can_cast(kind, self._values.dtype,
                                                                  casting="same_kind"):
                raise ValueError("fill_value must be either 'None' or of a type compatible "
                                 "with values")
        return fill_value

    @property
    def grid(self) -> tuple:
        return self._grid

    @property
    def values(self):
        return self._values

    def _fit(self, method: str, solver=None, solver_args=None) -> NdBSpline:
        """The tensor B-spline of a spline method (a legacy one's is the same), refusing
        values that are not finite with SciPy's message for the method."""
        k = (_DEGREES[method],) * len(self._grid)
        values = np.asarray(self._values)
        if not np.isfinite(values).all():
            raise ValueError("Array must not contain infs or nans." if method.endswith("_legacy")
                             else "RHS must contain only finite numbers")
        if solver is None and not solver_args:
            t, c = fit_grid(self._grid, values, k)
        else:
            t, c = _solved_by(solver, solver_args, self._grid, values, k)
        return NdBSpline._made(t, c, k, self.context)

    def __call__(self, xi, method=None, *, nu=None):
        """Values (or, spline methods, derivatives of orders nu, one per axis) at xi
        (..., ndim): shape xi.shape[:-1] + values.shape[ndim:] (a 1-D xi is one point)."""
        method = self._method(method, nu)
        ndim = len(self._grid)
        xi = coordinates(xi, ndim)
        if xi.shape[-1] != ndim:
            raise ValueError(f"The requested sample points xi have dimension {xi.shape[-1]} "
                             f"but this RegularGridInterpolator has dimension {ndim}")
        shape = xi.shape
        xi = np.asarray(xi, dtype=np.float64).reshape(-1, ndim)
        nans, outside = self._bounds(xi)
        if method == "nearest":
            result = self._nearest(xi)
        elif method == "linear":
            result = self._linear(xi)
        elif method == "pchip":
            result = self._pchip(xi)
        else:
            result = self._tensor(method)(xi, nu=nu)
        return self._filled(result, nans, outside).reshape(shape[:-1] +
                                                           self._values.shape[ndim:])

    def _method(self, method, nu) -> str:
        """The method of a call (None: the interpolator's), checked with its nu."""
        method = self.method if method is None else method
        if method not in _METHODS:
            raise ValueError(f"Method '{method}' is not defined")
        if nu is not None and method not in _SPLINES:
            raise ValueError(f"Can only compute derivatives for methods {_SPLINES}, got "
                             f"{method =}.")
        if method != self.method and method in _DEGREES:
            _spline_points(self._grid, method)
        return method

    def _bounds(self, xi: np.ndarray) -> tuple:
        """The points (N, ndim) checked against the grid: a ValueError naming the dimension
        where `bounds_error`; else (the NaN rows or None, the rows outside or None)."""
        ndim = len(self._grid)
        # Each axis' smallest and largest coordinate in one pass (NaN where a coordinate is:
        # it hides the bounds, so the masks are made); the per-point masks only where needed.
        if len(xi):
            lo, hi = (np.array(v) for v in _native.column_ranges(np.require(xi, np.float64,
                                                                            ["C", "A"])))
        else:
            lo, hi = (np.zeros(ndim),) * 2
        nans = np.isnan(xi).any(axis=-1) if np.isnan(lo).any() else None
        outside = None
        if self.bounds_error:
            for a in range(ndim):
                if not (self._grid[a][0] <= lo[a] and hi[a] <= self._grid[a][-1]):
                    raise ValueError(f"One of the requested xi is out of bounds in dimension "
                                     f"{a}")
        elif nans is not None or any(lo[a] < g[0] or hi[a] > g[-1]
                                     for a, g in enumerate(self._grid)):
            outside = np.zeros(len(xi), dtype=bool)
            for a, p in enumerate(xi.T):
                outside |= (p < self._grid[a][0]) | (p > self._grid[a][-1])
        return nans, outside

    def _filled(self, result: np.ndarray, nans, outside) -> np.ndarray:
        if outside is not None and self.fill_value is not None:
            result[outside] = self.fill_value
        if nans is not None:
            result[nans] = np.nan
        return result

    def _tensor(self, method: str) -> NdBSpline:
        """The tensor B-spline of a spline method: the fitted one for the interpolator's own
        method, else fitted now (not kept: a call does not change the interpolator)."""
        if method == self.method and self._spline is not None:
            return self._spline
        return self._fit(method)

    def _linear_tensor(self):
        """The multilinear interpolant as a degree-1 tensor B-spline on the grid's nodes (its
        coefficients are the values) over the axes longer than one node (constant along the
        others), and those axes; None for values that are not an array."""
        if not isinstance(self._values, np.ndarray):
            return None
        kept = [a for a, g in enumerate(self._grid) if len(g) > 1]
        if not kept:
            return None
        values = self._values[tuple(slice(None) if a in kept else 0
                                    for a in range(len(self._grid)))]
        t = tuple(np.concatenate([g[:1], g, g[-1:]]) for g in (self._grid[a] for a in kept))
        return NdBSpline._made(t, values, (1,) * len(kept), self.context), kept

    def _nearest(self, xi: np.ndarray):
        index = []
        for a, p in enumerate(xi.T):
            g = self._grid[a]
            if len(g) == 1:
                index.append(np.zeros(len(p), dtype=np.intp))
                continue
            i = np.clip(np.searchsorted(g, p) - 1, 0, len(g) - 2)
            with np.errstate(invalid="ignore"):
                along = (p - g[i]) / (g[i + 1] - g[i])
            index.append(np.where(along <= 0.5, i, i + 1))
        return np.array(self._values[tuple(index)], copy=True)

    def _linear(self, xi: np.ndarray) -> np.ndarray:
        """Multilinear (see `_linear_tensor`); values that are not an array (an object NumPy
        cannot convert but that indexes as one) are read corner by corner."""
        if not isinstance(self._values, np.ndarray):
            return self._linear_indexed(xi)
        made = self._linear_tensor()
        if made is None:  # every axis one node: the value, promoted as SciPy's linear does
            value = np.asarray(self._values, dtype=np.result_type(self._values.dtype,
                                                                  np.float64))
            return np.repeat(value.reshape((1, *value.shape[len(self._grid):])), len(xi),
                             axis=0)
        spline, kept = made
        return spline(np.ascontiguousarray(xi[:, kept]))

    def _linear_indexed(self, xi: np.ndarray) -> np.ndarray:
        lower, weights = [], []
        for a, p in enumerate(xi.T):
            g = self._grid[a]
            i = np.clip(np.searchsorted(g, p) - 1, 0, max(len(g) - 2, 0))
            step = g[np.minimum(i + 1, len(g) - 1)] - g[i]
            with np.errstate(invalid="ignore", divide="ignore"):
                along = np.where(step > 0, (p - g[i]) / np.where(step > 0, step, 1), 0.0)
            lower.append(i)
            weights.append(along)
        result = 0.0
        for corner in itertools.product((0, 1), repeat=len(self._grid)):
            index = tuple(np.minimum(i + c, len(g) - 1)
                          for i, c, g in zip(lower, corner, self._grid))
            weight = np.prod([w if c else 1 - w for w, c in zip(weights, corner)], axis=0)
            values = np.asarray(self._values[index])
            result = result + values * weight.reshape(weight.shape + (1,) * (values.ndim - 1))
        return np.asarray(result, dtype=np.float64)

    def _pchip(self, xi: np.ndarray) -> np.ndarray:
        d = len(self._grid)
        if d > 1 and np.isnan(xi[:, 1:]).any():
            # SciPy folds the later axes first through PchipInterpolator, which refuses the
            # NaN values a NaN coordinate there makes.
            raise ValueError("xi: a NaN coordinate in dimension 1 or later, which method "
                             "'pchip' refuses (as SciPy: `y` must contain only finite values)")
        values = np.asarray(self._values, dtype=np.float64)
        if not np.isfinite(values).all():
            raise ValueError("`y` must contain only finite values.")
        columns = np.require(values.reshape(int(np.prod(values.shape[:d])), -1), np.float64,
                             ["C", "A"])
        points = np.require(xi, np.float64, ["C", "A"])
        return _native.pchip_grid(list(self._grid), columns, points).reshape(
            (len(xi), *values.shape[d:]))


def _solved_by(solver, solver_args: dict, grid: tuple, values: np.ndarray, k: tuple) -> tuple:
    """SciPy's construction with the caller's solver: the global collocation system (its
    sparse design matrix at every grid node) handed to `solver(A, b, **solver_args)` per
    column, as SciPy does (`scipy.sparse.linalg.spsolve` returns the solution; an iterative
    solver returns (x, info), info != 0 a ValueError). A signature that cannot take them is a
    TypeError before any work."""
    import scipy.sparse.linalg as ssl

    solver = ssl.gcrotmk if solver is None else solver
    iterative = solver is not ssl.spsolve
    if iterative and "atol" not in solver_args:
        solver_args = {**solver_args, "atol": 1e-6}
    try:
        signature = inspect.signature(solver)
    except (TypeError, ValueError):
        signature = None  # a callable without a signature to read (a builtin)
    if signature is not None:
        try:
            signature.bind(None, None, **solver_args)
        except TypeError as e:
            raise TypeError(f"solver: cannot be called as solver(A, b, **solver_args) with "
                            f"solver_args {sorted(solver_args)}: {e}") from None
    d = len(grid)
    t = tuple(_collocation.not_a_knot(g, ka) for g, ka in zip(grid, k))
    nodes = np.asarray(list(itertools.product(*grid)), dtype=np.float64)
    matrix = NdBSpline.design_matrix(nodes, t, k)
    rhs = values.reshape(int(np.prod(values.shape[:d])), -1)

    def solve(b):
        if not iterative:
            return solver(matrix, b, **solver_args)
        x, info = solver(matrix, b, **solver_args)
        if info != 0:
            raise ValueError(f"{solver = } returns {info = }.")
        return x

    def columns(b):
        return np.stack([solve(b[:, j]) for j in range(b.shape[1])], axis=1)

    if np.iscomplexobj(rhs):
        c = columns(rhs.real) + 1j * columns(rhs.imag)
    else:
        c = columns(rhs)
    return t, c.reshape(values.shape)


def interpn(points, values, xi, method="linear", bounds_error=True, fill_value=np.nan, *,
            context=None):
    """SciPy's `interpn`: `RegularGridInterpolator(points, values, method, bounds_error,
    fill_value)(xi)`, and "splinef2d" (2-D scalar data, no extrapolation: the
    RectBivariateSpline through it, `fill_value` outside)."""
    known = [*_METHODS, "splinef2d"]
    if method not in known:
        raise ValueError("interpn only understands the methods 'linear', 'nearest', "
                         "'slinear', 'cubic', 'quintic', 'pchip', and 'splinef2d'. You "
                         f"provided {method}.")
    if not hasattr(values, "ndim"):
        values = np.asarray(values)
    ndim = values.ndim
    if ndim > 2 and method == "splinef2d":
        raise ValueError("The method splinef2d can only be used for 2-dimensional input data")
    if not bounds_error and fill_value is None and method == "splinef2d":
        raise ValueError("The method splinef2d does not support extrapolation.")
    if len(points) > ndim:
        raise ValueError(f"There are {len(points)} point arrays, but values has {ndim} "
                         f"dimensions")
    if len(points) != ndim and method == "splinef2d":
        raise ValueError("The method splinef2d can only be used for scalar data with one "
                         "point per coordinate")
    grid, _ = _axes(points)
    _check_shape(grid, values)
    xi = coordinates(xi, len(grid))
    if xi.shape[-1] != len(grid):
        raise ValueError(f"The requested sample points xi have dimension {xi.shape[-1]}, but "
                         f"this RegularGridInterpolator has dimension {len(grid)}")
    if method != "splinef2d":
        # The interpolator checks the bounds (one pass, the same message).
        return RegularGridInterpolator(points, values, method=method,
                                       bounds_error=bounds_error, fill_value=fill_value,
                                       context=context)(xi)
    if bounds_error:
        for a, p in enumerate(np.asarray(xi, dtype=np.float64).reshape(-1, len(grid)).T):
            if not np.all((grid[a][0] <= p) & (p <= grid[a][-1])):
                raise ValueError(f"One of the requested xi is out of bounds in dimension {a}")
    shape = xi.shape
    xi = np.asarray(xi, dtype=np.float64).reshape(-1, 2)
    inside = ((grid[0][0] <= xi[:, 0]) & (xi[:, 0] <= grid[0][-1])
              & (grid[1][0] <= xi[:, 1]) & (xi[:, 1] <= grid[1][-1]))
    if np.iscomplexobj(values):
        import warnings

        warnings.warn("splinef2d: complex values, of which only the real part is used",
                      np.exceptions.ComplexWarning, stacklevel=2)
        values = np.real(values)
    result = np.empty(len(xi))
    spline = RectBivariateSpline(points[0], points[1], values[:])
    result[inside] = spline.ev(xi[inside, 0], xi[inside, 1])
    result[~inside] = fill_value
    return result.reshape(shape[:-1])
