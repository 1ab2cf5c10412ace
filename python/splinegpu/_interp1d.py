"""SciPy's `interp1d`: every kind ("linear", "nearest", "nearest-up", "zero", "slinear",
"quadratic", "cubic", "previous", "next", or an integer degree), its bounds and fill rules,
any axis. The spline kinds are this package's `make_interp_spline` evaluated through a
`Context`; the others are NumPy index arithmetic, as SciPy's."""

from __future__ import annotations

from typing import Any, Literal

import numpy as np

from ._bsplines import BSpline, make_interp_spline
from ._context import Context

_ORDERS = {"zero": 0, "slinear": 1, "quadratic": 2, "cubic": 3}


def _extrapolates(fill_value) -> bool:
    return isinstance(fill_value, str) and fill_value == "extrapolate"


def _broadcast_up_to(value: np.ndarray, shape: tuple, name: str) -> np.ndarray:
    """`value` as one entry per column of y (shape: y's other axes), as SciPy broadcasts it."""
    if len(shape) >= value.ndim and all(f in (1, t) for t, f in zip(shape[::-1],
                                                                     value.shape[::-1])):
        if value.size != 1 and value.shape != shape:
            value = np.ones(shape, value.dtype) * value
        return value.ravel()
    raise ValueError(f"{name} argument must be able to broadcast up to shape {shape} but had "
                     f"shape {value.shape}")


class interp1d:
    """`scipy.interpolate.interp1d(x, y, kind="linear", axis=-1, copy=True,
    bounds_error=None, fill_value=nan, assume_sorted=False)`, with SciPy's results, errors
    and attributes (x, y, axis, bounds_error, fill_value, copy). `context` evaluates the
    spline kinds (zero to any degree) on a GPU context; the rest run in NumPy."""

    # The spline kinds' B-spline; the neighbour kinds' boundaries and search side.
    _spline: Any
    _bounds: np.ndarray
    _shift: np.ndarray
    _side: Literal["left", "right"]
    _ind: int

    def __init__(self, x, y, kind="linear", axis: int = -1, copy: bool = True,
                 bounds_error=None, fill_value=np.nan, assume_sorted: bool = False,
                 context: Context | None = None):
        self.bounds_error = bounds_error
        self.copy = copy
        if isinstance(kind, str) and kind in _ORDERS:
            order, kind = _ORDERS[kind], "spline"
        elif isinstance(kind, (int, np.integer)) and not isinstance(kind, bool):
            if kind < 0:
                raise ValueError(f"kind: a spline's order must be >= 0, got {int(kind)}")
            order, kind = int(kind), "spline"
        elif not (isinstance(kind, str) and kind in ("linear", "nearest", "nearest-up",
                                                      "previous", "next")):
            raise NotImplementedError(f"{kind} is unsupported: Use fitpack routines for other "
                                      f"types.")
        x = np.array(x, copy=True)
        y = np.array(y, copy=True)
        if y.ndim == 0:
            raise ValueError("the y array must have at least one dimension.")
        if not -y.ndim <= axis < y.ndim:
            raise np.exceptions.AxisError(f"axis: {axis} is out of bounds for y of {y.ndim} "
                                          f"dimensions")
        if x.ndim >= 1 and y.shape[axis] != len(x):
            raise ValueError("x and y arrays must be equal in length along interpolation "
                             "axis.")
        if not assume_sorted:
            order_of = np.argsort(x, kind="mergesort")
            x, y = x[order_of], np.take(y, order_of, axis=axis)
        if x.ndim != 1:
            raise ValueError("the x array must have exactly one dimension.")
        if y.dtype.kind not in "fc":
            y = y.astype(np.float64)
        self.axis = axis % y.ndim
        self.y, self.x = y, x
        self._extra = y.shape[:self.axis] + y.shape[self.axis + 1:]
        self._columns = np.moveaxis(y, self.axis, 0).reshape(len(x), -1)
        self._kind, self._spline, self._nan_spline = kind, None, False
        # SciPy's shortcut (which a single point needs): NumPy's interp for float64 or int
        # x and 1-D y when not extrapolating.
        plain = (np.dtype(np.float64), np.dtype(int))
        self._np_interp = (x.dtype in plain and y.dtype in plain and y.ndim == 1
                           and not _extrapolates(fill_value))
        minimum = 1
        if kind == "spline":
            minimum = order + 1
            if len(x) >= minimum:
                self._spline = self._fitted(order, context)
        elif kind in ("nearest", "nearest-up"):
            half = x / 2.0
            self._bounds = half[1:] + half[:-1]
            self._side = "left" if kind == "nearest" else "right"
        elif kind in ("previous", "next"):
            ahead = kind == "next"
            self._side, self._ind = ("right", 1) if ahead else ("left", 0)
            self._shift = np.nextafter(x, np.inf if ahead else -np.inf)
            if _extrapolates(fill_value):
                self._refuse_extrapolating_and_raising()
                end = np.take(y, 0 if ahead else -1, axis)
                fill_value = (end, np.nan) if ahead else (np.nan, end)
        if len(x) < minimum:
            raise ValueError(f"x and y arrays must have at least {minimum} entries")
        self.fill_value = fill_value

    def _fitted(self, order: int, context):
        """The spline kind's B-spline (SciPy's make_interp_spline with check_finite off: a NaN
        in x or y makes every value NaN for degree 2 and up)."""
        x = self.x
        columns = self._columns.astype(np.complex128 if np.iscomplexobj(self._columns) else
                                       np.float64)
        if order <= 1:
            # SciPy's make_interp_spline (these kinds' fit) refuses a repeated x.
            if np.any(x[1:] == x[:-1]):
                raise ValueError("Expect x to not have duplicates")
            knots = np.concatenate([x, x[-1:]] if order == 0 else [x[:1], x, x[-1:]])
            return BSpline.construct_fast(np.ascontiguousarray(knots, dtype=np.float64),
                                          np.ascontiguousarray(columns), order,
                                          context=context)
        if np.isnan(x).any():
            if np.isnan(x).all():
                raise ValueError("`x` array is all-nan")
            x = np.linspace(np.nanmin(x), np.nanmax(x), len(x))
            self._nan_spline = True
        if np.isnan(columns).any():
            columns = np.ones_like(columns)
            self._nan_spline = True
        return make_interp_spline(x, columns, k=order, context=context)

    @property
    def fill_value(self):
        """The fill value (as given)."""
        return self._fill_value_given

    @fill_value.setter
    def fill_value(self, fill_value) -> None:
        if _extrapolates(fill_value):
            self._refuse_extrapolating_and_raising()
            self._extrapolate = True
        else:
            shape = self._extra or (1,)
            if isinstance(fill_value, tuple) and len(fill_value) == 2:
                below = _broadcast_up_to(np.asarray(fill_value[0]), shape,
                                         "fill_value (below)")
                above = _broadcast_up_to(np.asarray(fill_value[1]), shape,
                                         "fill_value (above)")
            else:
                below = above = _broadcast_up_to(np.asarray(fill_value), shape, "fill_value")
            self._below, self._above = below, above
            self._extrapolate = False
            if self.bounds_error is None:
                self.bounds_error = True
        self._fill_value_given = fill_value

    def _refuse_extrapolating_and_raising(self) -> None:
        if self.bounds_error:
            raise ValueError("Cannot extrapolate and raise at the same time.")
        self.bounds_error = False

    def _values(self, x_new: np.ndarray) -> np.ndarray:
        x, y = self.x, self._columns
        if self._kind == "linear" and self._np_interp:
            return np.interp(x_new, x, y[:, 0])[:, None]
        if self._kind == "linear":
            hi = np.clip(np.searchsorted(x, x_new), 1, len(x) - 1)
            lo = hi - 1
            slope = (y[hi] - y[lo]) / (x[hi] - x[lo])[:, None]
            return slope * (x_new - x[lo])[:, None] + y[lo]
        if self._kind in ("nearest", "nearest-up"):
            index = np.clip(np.searchsorted(self._bounds, x_new, side=self._side), 0,
                            len(x) - 1)
            return y[index]
        if self._kind in ("previous", "next"):
            index = np.searchsorted(self._shift, x_new, side=self._side)
            index = np.clip(index, 1 - self._ind, len(x) - self._ind)
            return y[index + self._ind - 1]
        values = np.asarray(self._spline(x_new))
        if self._nan_spline:
            values = np.full_like(values, np.nan)
        return values.reshape(len(x_new), -1)

    def _check_bounds(self, x_new: np.ndarray):
        """(below, above): which x_new lie outside [x_0, x_last]; ValueError for one when
        bounds_error is set (SciPy's words)."""
        below, above = x_new < self.x[0], x_new > self.x[-1]
        if self.bounds_error and below.any():
            raise ValueError(f"A value ({x_new[np.argmax(below)]}) in x_new is below the "
                             f"interpolation range's minimum value ({self.x[0]}).")
        if self.bounds_error and above.any():
            raise ValueError(f"A value ({x_new[np.argmax(above)]}) in x_new is above the "
                             f"interpolation range's maximum value ({self.x[-1]}).")
        return below, above

    def __call__(self, x_new) -> np.ndarray:
        """The interpolant at x_new (any shape): x_new's shape in place of y's axis."""
        x_new = np.asarray(x_new)
        if x_new.dtype.kind not in "fc":
            x_new = x_new.astype(np.float64)
        shape = x_new.shape
        flat = x_new.ravel()
        values = self._values(flat)
        if not self._extrapolate:
            below, above = self._check_bounds(flat)
            if len(values):
                values[below] = self._below
                values[above] = self._above
        values = np.asarray(values).reshape(shape + self._extra)
        if self.axis != 0 and shape != ():
            nx, ny = len(shape), len(self._extra)
            order = (list(range(nx, nx + self.axis)) + list(range(nx))
                     + list(range(nx + self.axis, nx + ny)))
            values = values.transpose(order)
        return values
