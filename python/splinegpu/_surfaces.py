"""Surfaces from NumPy: `Context.tessellate_surfaces` and what it returns,
`SurfaceTessellation` (the command line's NPZ arrays, by the same names)."""

from __future__ import annotations

from typing import Any

import numpy as np

from . import _native
from ._helpers import _float64, _one_sampling, _order

# The arrays of a result, by the NPZ's names, in its order.
_ARRAYS = ("uv", "points", "du", "dv", "duu", "duv", "dvv", "normals", "triangles",
           "surface_offsets", "triangle_offsets", "patch")


class SurfaceTessellation:
    """The vertices and triangles of a `Context.tessellate_surfaces` call, as the command
    line's NPZ holds them: `uv` (N, 2) float64; `points` (N, D); `du`, `dv` (derivatives >= 1)
    and `duu`, `duv`, `dvv` (derivatives 2), `normals` (N, 3) when asked for, else None
    (float64 from the CPU, float32 from the GPU); `triangles` (M, 3) int64 indexing the whole
    vertex array; `surface_offsets` and `triangle_offsets` (S + 1,) int64 (surface s owns
    vertices surface_offsets[s]:surface_offsets[s+1] and likewise triangles); `patch` (N,)
    int64 (the patch each vertex was evaluated on, -1 on nets' vertices) when a patch list is
    present, else None."""

    __slots__ = _ARRAYS
    uv: np.ndarray
    points: np.ndarray
    du: np.ndarray | None
    dv: np.ndarray | None
    duu: np.ndarray | None
    duv: np.ndarray | None
    dvv: np.ndarray | None
    normals: np.ndarray | None
    triangles: np.ndarray
    surface_offsets: np.ndarray
    triangle_offsets: np.ndarray
    patch: np.ndarray | None

    def __init__(self, arrays: dict):
        for name in _ARRAYS:
            setattr(self, name, arrays.get(name))

    def arrays(self) -> dict:
        """The arrays present, by name: `numpy.savez(path, **result.arrays())` writes the NPZ
        the command line writes."""
        return {name: getattr(self, name) for name in _ARRAYS if getattr(self, name) is not None}

    def __len__(self) -> int:
        return len(self.uv)

    def surface(self, s: int) -> dict:
        """Surface s's arrays (views; its triangles indexing its own vertices, a new array)."""
        a, b = self.surface_offsets[s], self.surface_offsets[s + 1]
        p, q = self.triangle_offsets[s], self.triangle_offsets[s + 1]
        out = {name: getattr(self, name)[a:b] for name in (*_ARRAYS[:8], "patch")
               if getattr(self, name) is not None}
        out["triangles"] = self.triangles[p:q] - a
        return out

    def trimesh(self, s: int | None = None):
        """A `trimesh.Trimesh` of every surface (or of surface s): the positions (float64, a
        view on the CPU; float32 from the GPU, converted once) and the triangles as they are,
        with the normals as vertex normals when asked for; `process=False`, so trimesh keeps
        the vertices as given (a shared edge's vertices are already one)."""
        import trimesh

        arrays = self.arrays() if s is None else self.surface(s)
        return trimesh.Trimesh(vertices=arrays["points"], faces=arrays["triangles"],
                               vertex_normals=arrays.get("normals"), process=False)

    def __repr__(self) -> str:
        return (f"SurfaceTessellation({len(self.surface_offsets) - 1} surfaces, {len(self.uv)} "
                f"vertices, {len(self.triangles)} triangles, points {self.points.dtype} "
                f"{self.points.shape})")


def _per_surface(name: str, value, surfaces: int, ndim: int):
    """A per-surface array field: one array for every surface, or a list with one per
    surface; None when not given."""
    if value is None:
        return None
    if isinstance(value, (list, tuple)) and len(value) == surfaces and all(
            np.ndim(v) == ndim for v in value):
        items = [_float64(v, f"{name}[{s}]") for s, v in enumerate(value)]
    else:
        one = _float64(value, name)
        if one.ndim != ndim:
            raise ValueError(f"{name}: must be a {ndim}-D array (or a list of one per surface), "
                             f"got shape {one.shape}")
        items = [one] * surfaces
    return [np.require(v, np.float64, ["C", "A"]) for v in items]


def _pair(name: str, value, allowed=None):
    if value is None:
        return None
    pair = (value, value) if isinstance(value, str) else tuple(value)
    if len(pair) != 2 or not all(isinstance(v, str) for v in pair):
        raise ValueError(f"{name}: must be one name or a pair (u, v), got {value!r}")
    return pair


def surface_arguments(nets, *, ends=None, tension=None, bias=None, matrix=None, patches=None,
                      conditions=None, u=None, v=None, knots_u=None, knots_v=None,
                      weights=None) -> tuple[list, dict]:
    """The nets (each a C-ordered, aligned (n_u, n_v, D) float64 array; a patch list's points
    as one column) and the kind's fields, as the extension takes them, every refusal named."""
    if patches is not None:
        # Patch lists: each surface's control points (n, D), a net of one column.
        points = [_float64(p, f"nets[{s}]") for s, p in enumerate(nets)] \
            if not (isinstance(nets, np.ndarray) and nets.ndim == 2) else [_float64(nets, "nets")]
        for s, p in enumerate(points):
            if p.ndim != 2:
                raise ValueError(f"nets[{s}]: a patch list's control points must be (n, D), "
                                 f"got shape {p.shape}")
        nets3 = [p[:, None, :] for p in points]
    else:
        if isinstance(nets, np.ndarray) and nets.ndim == 3:
            nets = [nets]
        nets3 = [_float64(n, f"nets[{s}]") for s, n in enumerate(nets)]
        for s, n in enumerate(nets3):
            if n.ndim != 3:
                raise ValueError(f"nets[{s}]: a net must be (n_u, n_v, D), got shape {n.shape}")
    nets3 = [np.require(n, np.float64, ["C", "A"]) for n in nets3]
    count = len(nets3)
    if patches is not None:
        lists = patches if isinstance(patches, (list, tuple)) and len(patches) == count and all(
            np.ndim(p) == 2 for p in patches) else [patches] * count
        patches = []
        for s, p in enumerate(lists):
            p = np.asarray(p)
            if p.ndim != 2 or p.shape[1] != 16 or not np.issubdtype(p.dtype, np.integer):
                raise ValueError(f"patches[{s}]: must be (P, 16) integer indices, got "
                                 f"{p.dtype} {p.shape}")
            if p.dtype.kind == "u" and p.size and p.max() > np.iinfo(np.int64).max:
                # int64 would wrap it to a negative index: name the value given.
                raise ValueError(f"patches[{s}]: index {int(p.max())} is beyond the "
                                 f"{len(nets3[s])} points")
            patches.append(np.require(p, np.int64, ["C", "A"]))
    fields = {
        "ends": _pair("ends", ends),
        "tension": None if tension is None else float(tension),
        "bias": None if bias is None else float(bias),
        "matrix": None if matrix is None else [[float(x) for x in row] for row in matrix],
        "patches": patches,
        "conditions": _pair("conditions", conditions),
        "u": _per_surface("u", u, count, 1),
        "v": _per_surface("v", v, count, 1),
        "knots_u": _per_surface("knots_u", knots_u, count, 1),
        "knots_v": _per_surface("knots_v", knots_v, count, 1),
        "weights": _per_surface("weights", weights, count, 2),
    }
    return nets3, fields


def tessellate_surfaces(context, nets, kind: str = "bspline", *, ends=None, tension=None,
                        bias=None, matrix=None, patches=None, conditions=None, u=None, v=None,
                        knots_u=None, knots_v=None, weights=None, per_segment=None, at=None,
                        tolerance=None, derivatives: int = 0, normals: bool = False,
                        out: SurfaceTessellation | None = None) -> SurfaceTessellation:
    """See `Context.tessellate_surfaces`."""
    nets3, fields = surface_arguments(nets, ends=ends, tension=tension, bias=bias, matrix=matrix,
                                      patches=patches, conditions=conditions, u=u, v=v,
                                      knots_u=knots_u, knots_v=knots_v, weights=weights)
    count = len(nets3)
    name, value = _one_sampling({"per_segment": per_segment, "at": at, "tolerance": tolerance},
                                ("per_segment", 16))
    sampling: Any
    if name == "per_segment":
        ks = (value, value) if np.ndim(value) == 0 else tuple(value)
        if len(ks) != 2 or any(int(k) != k or not 1 <= k < 2**32 for k in ks):
            raise ValueError(f"per_segment: must be a count from 1 to 2^32 - 1 or a pair "
                             f"(k_u, k_v) of them, got {value!r}")
        sampling = (int(ks[0]), int(ks[1]))
    elif name == "at":
        sampling = _per_surface("at", value, count, 2)
    else:
        sampling = float(_float64(value, "tolerance"))
    reuse = None if out is None else out.arrays()
    arrays = _native.tessellate_surfaces(context._native, nets3, str(kind), fields, sampling,
                                         _order("derivatives", derivatives, 2), bool(normals),
                                         reuse)
    return SurfaceTessellation(arrays)
