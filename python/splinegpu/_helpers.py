"""The package's one helpers module: arguments as the extension takes them (float64, aligned
and C-contiguous arrays, per-curve fields as one (C, k) array where the curves' share a shape,
SciPy's `extrapolate`), every refusal naming the argument. Its names are the only private ones
that other modules import (tests/test_layers.py holds every module to that)."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


def _float64(a, name: str) -> np.ndarray:
    """`a` as a float64 array (itself where it already is one). Complex values are refused,
    naming `name`, rather than cut to their real part."""
    try:
        a = np.asarray(a)
    except ValueError as e:
        # A nested list whose rows differ in length.
        raise ValueError(f"{name}: {e}") from None
    if np.iscomplexobj(a):
        raise ValueError(f"{name}: complex values are not supported (got {a.dtype}); pass the "
                         f"real and imaginary parts as coordinates of their own")
    if a.dtype.kind not in "biuf":
        # Strings would be parsed as numbers by astype, objects are ragged nested lists.
        raise TypeError(f"{name}: must be numbers, got an array of {a.dtype}"
                        + (" (rows of different lengths?)" if a.dtype.kind == "O" else ""))
    return a.astype(np.float64, copy=False)


def _order(name: str, value, most: int) -> int:
    """An integer argument `name` in 0..=most (a derivative order), refused by name otherwise."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not (
            0 <= value <= most):
        raise ValueError(f"{name}: must be an integer from 0 to {most}, got {value!r}")
    return int(value)


def _axis(value, ndim: int, of: str) -> int:
    """SciPy's `axis` of an ndim-D array (`of` names it: "y", "c"): an integer from -ndim to
    ndim - 1, refused by name otherwise; a negative axis counts from the end, and is returned
    normalised."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not (
            -ndim <= value < ndim):
        # NumPy's AxisError, a ValueError (and an IndexError), as SciPy raises.
        raise np.exceptions.AxisError(f"axis: must be an integer from {-ndim} to {ndim - 1} "
                                      f"for a {ndim}-D {of}, got {value!r}")
    return int(value) % ndim


def _natural(name: str, value) -> int:
    """An integer argument `name` >= 0 (a degree, a derivative order without a bound), refused
    by name otherwise."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
        raise ValueError(f"{name}: must be an integer >= 0, got {value!r}")
    return int(value)


def _count(name: str, value) -> int:
    """A sample count `name` (per_segment, arc_length): an integer (0 goes on to the crate,
    whose message names the curve)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer, float, np.floating)) \
            or not np.isfinite(value) or int(value) != value:
        raise ValueError(f"{name}: must be an integer, got {value!r}")
    if value < 0:
        raise ValueError(f"{name}: must be >= 1, got {value}")
    return int(value)


def _aligned(a, name: str) -> np.ndarray:
    """`a` (argument `name`) as an aligned, C-contiguous float64 array (itself where it already
    is one): arrays unpickled from a network buffer (Dask) may be misaligned."""
    return np.require(_float64(a, name), requirements=["C", "A"])


def _curves(points):
    """A (C, n, D) array (passed whole) or a list of (n_i, D) arrays (each made C-contiguous)."""
    if isinstance(points, np.ndarray):
        if points.ndim != 3:
            raise ValueError(f"points: must be a (C, n, D) array or a list of (n_i, D) arrays, "
                             f"got an array of shape {points.shape}")
        return _aligned(points, "points")
    if isinstance(points, (list, tuple)) and points and isinstance(points[0], np.ndarray) \
            and points[0].ndim == 2:
        stacked = _stacked(points)
        if stacked is not None:
            return _aligned(stacked, "points")
    out = []
    for c, p in enumerate(points):
        a = _float64(p, f"curve {c}: \"points\"")
        if a.ndim == 1:
            a = a[:, None]
        if a.ndim != 2:
            raise ValueError(f"curve {c}: \"points\" must be an (n, D) array, got shape {a.shape}")
        out.append(_aligned(a, "points"))
    return out


def _stacked(items, otherwise=None):
    """A list of arrays of one shape and type as one array (a copy), or None. Handing the
    extension thousands of views of one array made each borrow check the others (`list(arr)`
    of 40,000 curves took 2.4 s where the array took 0.07); one copy costs less than that.
    Anything else is returned as `otherwise`."""
    if not isinstance(items, (list, tuple)) or len(items) < 2:
        return otherwise
    first = items[0]
    if not isinstance(first, np.ndarray) or first.dtype.kind not in "biuf":
        return otherwise
    # np.array checks the shapes in C and copies faster than np.stack (docs/benchmarks.md);
    # another type among them shows in the result's.
    try:
        stacked = np.array(items)
    except (ValueError, TypeError):
        return otherwise
    return stacked if stacked.dtype == first.dtype else otherwise


def _matrix(matrix) -> list:
    """A basis matrix: 4 rows of 4 numbers."""
    m = _float64(matrix, "matrix")
    if m.shape != (4, 4):
        raise ValueError(f"matrix: must be 4 rows of 4 numbers, got shape {m.shape}")
    return m.tolist()


def _per_curve(name: str, value, curves: int, ndim: int):
    """A per-curve argument (t, at, derivatives, knots, ...) of `ndim` dimensions per curve: one
    array for all curves, an array of one more dimension (a row per curve) or a list of arrays
    (ragged). To the native side as one (C, k) array where every curve's has one shape (see
    `_stacked`), else as a list of flat arrays (or None)."""
    if value is None:
        return None
    if isinstance(value, np.ndarray) and value.ndim == ndim:
        value = [value] * curves
    else:
        stacked = value if isinstance(value, np.ndarray) else _stacked(value)
        if isinstance(stacked, np.ndarray) and stacked.ndim == ndim + 1:
            if len(stacked) != curves:
                raise ValueError(f"{name}: {len(stacked)} entries for {curves} curves")
            return _aligned(stacked.reshape(curves, stacked[0].size if curves else 0), name)
    value = list(value)
    if value and np.ndim(value[0]) == 0 and ndim == 1:
        value = [_float64(value, name)] * curves
    if len(value) != curves:
        raise ValueError(f"{name}: {len(value)} entries for {curves} curves")
    return [None if v is None else _flat(v, name) for v in value]


def _per_point(name: str, value, curves: int) -> dict:
    """A number for every curve (`name`), or per point or joint (`name + "_each"`: an array per
    curve)."""
    if value is None:
        return {name: None, f"{name}_each": None}
    if isinstance(value, (bool, np.bool_, str)):
        raise TypeError(f"{name}: must be a number or an array of numbers, got {value!r}")
    if isinstance(value, (int, float, np.integer, np.floating)):
        return {name: float(value), f"{name}_each": None}
    return {name: None, f"{name}_each": _per_curve(name, value, curves, 1)}


def _flat(v, name: str) -> np.ndarray:
    """`v` (argument `name`) as an aligned, contiguous 1-D float64 array (a view where it
    already is one)."""
    return _aligned(_float64(v, name).ravel(), name)


def _rows(name: str, value, curves: int):
    """Per-curve 1-D arrays for the native side: a (C, k) array whole, else a list."""
    if isinstance(value, np.ndarray) and value.ndim == 2:
        if len(value) != curves:
            raise ValueError(f"{name}: {len(value)} rows for {curves} curves")
        return _aligned(value, name)
    if isinstance(value, np.ndarray) and value.ndim == 1:
        return _aligned(np.broadcast_to(value, (curves, len(value))), name)
    return _per_curve(name, value, curves, 1)


def _one_sampling(options: dict, default: tuple) -> tuple:
    """The one sampling given among `options` (its name -> its value, or None where not
    given) as (name, value), else `default`; two given is a ValueError naming them."""
    given = [(name, value) for name, value in options.items() if value is not None]
    if len(given) > 1:
        raise ValueError(f"sampling: give one of {', '.join(options)}, got "
                         f"{', '.join(n for n, _ in given)}")
    return given[0] if given else default


def _curve_fields(curves: int, *, ends=None, tension=None, bias=None, continuity=None,
                  matrix=None, t=None, start_derivative=None, end_derivative=None, tangents=None,
                  method=None, knots=None, weights=None) -> dict:
    """A curve kind's fields for the native side, each normalised for `curves` curves (see
    `Context.tessellate`)."""
    return {
        "ends": ends,
        **_per_point("tension", tension, curves),
        **_per_point("continuity", continuity, curves),
        **_per_point("bias", bias, curves),
        "matrix": None if matrix is None else _matrix(matrix),
        "t": _per_curve("t", t, curves, 1),
        "start_derivative": _per_curve("start_derivative", start_derivative, curves, 1),
        "end_derivative": _per_curve("end_derivative", end_derivative, curves, 1),
        "tangents": _per_curve("tangents", tangents, curves, 2),
        "method": None if method is None else str(method),
        "knots": _per_curve("knots", knots, curves, 1),
        "weights": _per_curve("weights", weights, curves, 1),
    }


def _curve_sampling(curves: int, *, per_segment, at, arc_length, tolerance) -> tuple:
    """The one sampling of a curve call as (name, value) for the native side: per_segment=16
    by default; `at` one row per curve."""
    name, value = _one_sampling({"per_segment": per_segment, "at": at,
                                 "arc_length": arc_length, "tolerance": tolerance},
                                ("per_segment", 16))
    if name == "at":
        value = _rows("at", value, curves)
    elif name in ("per_segment", "arc_length"):
        value = _count(name, value)
    else:
        value = float(_float64(value, "tolerance"))
    return name, value


def _end_to_end(arrays, name: str) -> tuple:
    """A batch's arrays (a list of (n_i, ...) arrays, or one (S, n, ...) array) laid end to
    end as one aligned float64 array (sum n_i, ...), and the (S + 1,) int64 offsets where each
    starts: the extension borrows two arrays, not one per series."""
    if isinstance(arrays, np.ndarray) and arrays.ndim >= 2:
        count, n = arrays.shape[:2]
        flat = arrays.reshape((count * n, *arrays.shape[2:]))
        offsets = np.arange(count + 1, dtype=np.int64) * n
    else:
        arrays = list(arrays)
        lengths = [len(a) for a in arrays]
        offsets = np.concatenate([[0], np.cumsum(lengths, dtype=np.int64)]).astype(np.int64)
        flat = np.concatenate(arrays) if arrays else np.zeros(0)
    return _aligned(flat, name), offsets


class _Laid(NamedTuple):
    """A batch's arrays already laid end to end, as `_end_to_end` lays them (`flat`, and the
    (S + 1,) `offsets` where each starts): what the extension takes, without a copy."""

    flat: np.ndarray
    offsets: np.ndarray

    def parts(self) -> list:
        """Each series' array, a view of `flat`."""
        return np.split(self.flat, self.offsets[1:-1])


def _owner(a: np.ndarray):
    """The object whose memory `a` views (`a` itself where it owns its data)."""
    while isinstance(a.base, np.ndarray):
        a = a.base
    return a if a.base is None else a.base


# The mean rows a batch's arrays need to be borrowed one by one rather than copied end to
# end: per array, the checks below and a borrow cost about what copying 2,000 values does.
_LONG = 1024


def _batch(arrays, name: str, ndim: int):
    """A batch's arrays (a list of `ndim`-D arrays, or one array of one dimension more) as the
    extension takes them: that one array; for long arrays, the list, each aligned, where no two
    view one owner's memory (each borrowed on its own, nothing copied); else laid end to end
    with their offsets (`_end_to_end`), as for short arrays copying is cheaper, and as NumPy's
    borrow checks compare every view of one owner with every other (16,000 views of one
    array: 0.3 s)."""
    if isinstance(arrays, np.ndarray) and arrays.ndim == ndim + 1:
        return _aligned(arrays, name)
    arrays = list(arrays)
    if sum(map(len, arrays)) < _LONG * len(arrays):
        return _end_to_end(arrays, name)
    arrays = [_aligned(a, f"{name}[{i}]") for i, a in enumerate(arrays)]
    for i, a in enumerate(arrays):
        if a.ndim != ndim:
            raise ValueError(f"{name}[{i}]: must be {ndim}-D, got shape {a.shape}")
    if len({id(_owner(a)) for a in arrays}) == len(arrays):
        return arrays
    return _end_to_end(arrays, name)


def _xs_and_weights(xs, ws, xname: str = "xs") -> tuple:
    """A batch's x (a list of 1-D arrays or a 2-D array) and weights (None for unit weights,
    or one 1-D array per series) as the extension takes them (`_batch`), and the (S + 1,)
    offsets where each series starts, were they laid end to end."""
    # A 2-D xs' rows are not made into arrays one by one (docs/benchmarks.md).
    lengths = [xs.shape[1]] * len(xs) if isinstance(xs, np.ndarray) else [len(x) for x in xs]
    offsets = np.concatenate([[0], np.cumsum(lengths, dtype=np.int64)]).astype(np.int64)
    if ws is None:
        return _batch(xs, xname, 1), None, offsets
    ws = [_float64(w, f"ws[{i}]") for i, w in enumerate(ws)]
    if len(ws) != len(lengths):
        raise ValueError(f"ws: {len(ws)} weight arrays for {len(lengths)} series")
    return _batch(xs, xname, 1), _batch(ws, "ws", 1), offsets


def _is_named(obj, name: str) -> bool:
    """Whether obj is an instance of a class called `name` (this package's or SciPy's: the
    conversions between bases take either)."""
    return any(cls.__name__ == name for cls in type(obj).__mro__)


def _extrapolate(value):
    """SciPy's `extrapolate`: True, False or "periodic" (None: the object's own)."""
    if value is None or isinstance(value, bool):
        return value
    if isinstance(value, str):
        if value != "periodic":
            raise ValueError(f"extrapolate: must be True, False or 'periodic', got {value!r}")
        return value
    return bool(value)


_F64 = np.dtype(np.float64)


def _f64(a) -> np.ndarray:
    """a as an aligned, C-contiguous float64 array for the extension (itself where it is one,
    checked first: a call of microseconds makes several): arrays unpickled from a network
    buffer (Dask) may be misaligned."""
    if a.__class__ is np.ndarray and a.dtype == _F64:
        flags = a.flags
        if flags.c_contiguous and flags.aligned:
            return a
    return np.require(a, dtype=np.float64, requirements=["C", "A"])
