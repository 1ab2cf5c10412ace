"""Strokes, tubes and ribbons from NumPy: `Context.strokes`, `Context.tubes` and
`Context.ribbons`, and what they return, `Meshes` (the command line's NPZ arrays for a
document with "geometry", by the same names)."""

from __future__ import annotations

import numpy as np

from . import _native
from ._helpers import _count, _curve_fields, _curve_sampling, _curves, _float64, _per_point

# The arrays of a result, by the NPZ's names, in its order.
_ARRAYS = ("points", "t", "normals", "triangles", "curve_offsets", "triangle_offsets")


class Meshes:
    """The meshes of a `Context.strokes`, `.tubes` or `.ribbons` call, one per curve, as the
    command line's NPZ holds them: `points` (N, 2) for strokes, (N, 3) for tubes and ribbons,
    float64 from the CPU and float32 from the GPU; `t` (N,) float64, the curve parameter each
    vertex was made at; `normals` (N, 3) unit normals of the exact surface for tubes and
    ribbons (as `points`), None for strokes; `triangles`
    (M, 3) int64, counter-clockwise, indexing the whole vertex array; `curve_offsets` and
    `triangle_offsets` (C + 1,) int64 (curve c owns vertices curve_offsets[c]:curve_offsets[c+1]
    and likewise triangles)."""

    __slots__ = _ARRAYS
    points: np.ndarray
    t: np.ndarray
    normals: np.ndarray | None
    triangles: np.ndarray
    curve_offsets: np.ndarray
    triangle_offsets: np.ndarray

    def __init__(self, arrays: dict):
        for name in _ARRAYS:
            setattr(self, name, arrays.get(name))

    def arrays(self) -> dict:
        """The arrays present, by name: `numpy.savez(path, **result.arrays())` writes the NPZ
        the command line writes."""
        return {name: getattr(self, name) for name in _ARRAYS if getattr(self, name) is not None}

    def __len__(self) -> int:
        return len(self.t)

    def curve(self, c: int) -> dict:
        """Curve c's mesh: its points, t and normals (views) and its triangles indexing its own
        vertices (a new array)."""
        a, b = self.curve_offsets[c], self.curve_offsets[c + 1]
        p, q = self.triangle_offsets[c], self.triangle_offsets[c + 1]
        out = {name: getattr(self, name)[a:b] for name in ("points", "t", "normals")
               if getattr(self, name) is not None}
        out["triangles"] = self.triangles[p:q] - a
        return out

    def trimesh(self, c: int | None = None):
        """A `trimesh.Trimesh` of every mesh (or of curve c's): a stroke's points at z = 0, the
        normals as vertex normals where there are any; `process=False`, so trimesh keeps the
        vertices as given."""
        import trimesh

        arrays = self.arrays() if c is None else self.curve(c)
        points = arrays["points"]
        if points.shape[1] == 2:
            points = np.column_stack([points, np.zeros(len(points))])
        return trimesh.Trimesh(vertices=points, faces=arrays["triangles"],
                               vertex_normals=arrays.get("normals"), process=False)

    def __repr__(self) -> str:
        return (f"Meshes({len(self.curve_offsets) - 1} curves, {len(self.t)} vertices, "
                f"{len(self.triangles)} triangles, points {self.points.dtype} "
                f"{self.points.shape})")


def _up(up):
    if up is None:
        return None
    a = _float64(up, "up")
    if a.shape != (3,):
        raise ValueError(f"up: must be 3 numbers, got shape {a.shape}")
    return tuple(float(x) for x in a)


def _dash(dash, dash_offset):
    if dash is None:
        if dash_offset is not None:
            raise ValueError("dash_offset: needs a dash pattern beside it (dash=)")
        return None, None
    a = _float64(dash, "dash")
    if a.ndim != 1:
        raise ValueError(f"dash: must be a 1-D array of lengths, got shape {a.shape}")
    offset = None if dash_offset is None else float(_float64(dash_offset, "dash_offset"))
    return [float(x) for x in a], offset


def _sides(sides):
    if sides is None:
        return None
    sides = _count("sides", sides)
    if sides >= 2**32:
        raise ValueError(f"sides: must be below 2^32, got {sides}")
    return sides


def _flag(name: str, value):
    if value is None or isinstance(value, (bool, np.bool_)):
        return None if value is None else bool(value)
    raise TypeError(f"{name}: must be True or False, got {value!r}")


def _name(name: str, value):
    if value is None or isinstance(value, str):
        return value
    raise TypeError(f"{name}: must be a string, got {value!r}")


def meshes(context, shape: str, points, kind: str, *, width, width_name: str, cap=None,
           join=None, miter_limit=None, sides=None, up=None, caps=None, dash=None,
           dash_offset=None, per_segment=None, at=None, arc_length=None, tolerance=None,
           out: Meshes | None = None, fields: dict) -> Meshes:
    """See `Context.strokes`, `Context.tubes` and `Context.ribbons`."""
    curves = _curves(points)
    sampling = _curve_sampling(len(curves), per_segment=per_segment, at=at,
                               arc_length=arc_length, tolerance=tolerance)
    kind_fields = _curve_fields(len(curves), **fields)
    widths = _per_point(width_name, width, len(curves))
    pattern, offset = _dash(dash, dash_offset)
    geometry = {
        "shape": shape,
        "width": widths[width_name],
        "width_each": widths[f"{width_name}_each"],
        "cap": _name("cap", cap),
        "join": _name("join", join),
        "miter_limit": None if miter_limit is None else float(_float64(miter_limit,
                                                                       "miter_limit")),
        "sides": _sides(sides),
        "up": _up(up),
        "caps": _flag("caps", caps),
        "dash": pattern,
        "dash_offset": offset,
    }
    reuse = None if out is None else out.arrays()
    return Meshes(_native.geometry_meshes(context._native, curves, str(kind), kind_fields,
                                          sampling, geometry, reuse))
