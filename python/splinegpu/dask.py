"""Tessellating more curves than one machine holds, on a Dask cluster.

    >>> from distributed import Client
    >>> import dask.array as da, splinegpu.dask
    >>> client = Client("scheduler:8786")                 # or LocalCluster()
    >>> curves = da.random.uniform(-1, 1, (10**8, 16, 3), chunks=(10**6, 16, 3))
    >>> r = splinegpu.dask.tessellate(curves, kind="bspline", per_segment=32)
    >>> r.points                                          # dask array, exact chunk sizes
    >>> r.points[:1000].compute()

Each partition (a block of whole curves of a dask.array, or a partition of a dask.bag of (n_i, D)
arrays) is tessellated (or made into meshes: `strokes`, `tubes`, `ribbons`) by the package in its
worker, on one `Context` per worker process made
once. Curves are independent, so throughput grows with workers. The partitions are computed once
and kept on the workers (`persist`); the result's dask arrays (t, points, d1, d2) have their real
chunk sizes, and `curve_offsets` is stitched across partitions into offsets of the whole batch.
A worker lost mid-run is handled by Dask: its partitions are computed again elsewhere.
`closest` answers a dask.array of query points block by block against one batch of curves.
"""

from __future__ import annotations

import threading
from typing import Any

import numpy as np

import splinegpu

_contexts: dict[str, splinegpu.Context] = {}
_lock = threading.Lock()


def worker_context(backend: str = "auto") -> splinegpu.Context:
    """This process's context for `backend`, made on first use and kept."""
    with _lock:
        if backend not in _contexts:
            _contexts[backend] = splinegpu.Context(backend)
        return _contexts[backend]


def _block(curves, backend: str, kwargs: dict[str, Any]):
    """One partition: (t, points, d1, d2, curve_offsets) of its curves, offsets from 0."""
    if not isinstance(curves, np.ndarray):
        curves = list(curves)
    r = worker_context(backend).tessellate(curves, **kwargs)
    return r.t, r.points, r.d1, r.d2, r.curve_offsets


class DaskTessellation:
    """`splinegpu.Tessellation`'s arrays as dask arrays: t, points, d1, d2 (None unless asked
    for) and curve_offsets over the whole batch."""

    def __init__(self, t, points, d1, d2, curve_offsets):
        self.t, self.points, self.d1, self.d2 = t, points, d1, d2
        self.curve_offsets = curve_offsets

    def compute(self) -> splinegpu.Tessellation:
        """Everything, gathered into one `splinegpu.Tessellation` in this process."""
        import dask

        arrays = dask.compute(self.t, self.points, self.d1, self.d2, self.curve_offsets)
        return splinegpu.Tessellation(*arrays)


def tessellate(curves, *, backend: str = "auto", **kwargs) -> DaskTessellation:
    """Tessellates a dask.array (C, n, D), chunked along its first axis only, or a dask.bag of
    (n_i, D) arrays, partition by partition on the cluster. `kwargs` are those of
    `splinegpu.Context.tessellate` (per-curve arrays such as `at` must be one array for all).
    """
    parts, meta = _persisted(curves, _block, backend, kwargs)
    t, points, d1, d2 = (_concatenated(parts, meta, index) for index in range(4))
    return DaskTessellation(t, points, d1, d2, _offsets(parts, meta, 4, 0))


def _mesh_block(curves, backend: str, method: str, kwargs: dict[str, Any]):
    """One partition's meshes: (points, t, normals, triangles, curve_offsets,
    triangle_offsets), its triangles and offsets counted from its own first vertex."""
    if not isinstance(curves, np.ndarray):
        curves = list(curves)
    m = getattr(worker_context(backend), method)(curves, **kwargs)
    return m.points, m.t, m.normals, m.triangles, m.curve_offsets, m.triangle_offsets


class DaskMeshes:
    """`splinegpu.Meshes`' arrays as dask arrays over the whole batch: points, t, normals (None
    for strokes), triangles indexing the whole vertex array, curve_offsets and
    triangle_offsets. Each partition's mesh arrays are one chunk."""

    def __init__(self, arrays: dict):
        self.points, self.t, self.normals = arrays["points"], arrays["t"], arrays["normals"]
        self.triangles = arrays["triangles"]
        self.curve_offsets = arrays["curve_offsets"]
        self.triangle_offsets = arrays["triangle_offsets"]

    def compute(self) -> splinegpu.Meshes:
        """Everything, gathered into one `splinegpu.Meshes` in this process."""
        import dask

        names = ("points", "t", "normals", "triangles", "curve_offsets", "triangle_offsets")
        arrays = dask.compute(*(getattr(self, name) for name in names))
        return splinegpu.Meshes(dict(zip(names, arrays)))


def _meshes(method: str, curves, backend: str, kwargs: dict[str, Any]) -> DaskMeshes:
    parts, meta = _persisted(curves, _mesh_block, backend, method, kwargs)
    points, t, normals = (_concatenated(parts, meta, index) for index in range(3))
    # Each partition's triangles moved by the vertices before it.
    vertex_starts = np.concatenate([[0], np.cumsum([m["shapes"][0][0] for m in meta])])
    triangles = _concatenated(parts, meta, 3, vertex_starts)
    return DaskMeshes({"points": points, "t": t, "normals": normals, "triangles": triangles,
                       "curve_offsets": _offsets(parts, meta, 4, 0),
                       "triangle_offsets": _offsets(parts, meta, 5, 3)})


def strokes(curves, *, backend: str = "auto", **kwargs) -> DaskMeshes:
    """`splinegpu.Context.strokes` on a dask.array or dask.bag of curves, as `tessellate`
    takes them, partition by partition on the cluster: one mesh array per partition."""
    return _meshes("strokes", curves, backend, kwargs)


def tubes(curves, *, backend: str = "auto", **kwargs) -> DaskMeshes:
    """`splinegpu.Context.tubes` on a dask.array or dask.bag of curves, as `strokes`."""
    return _meshes("tubes", curves, backend, kwargs)


def ribbons(curves, *, backend: str = "auto", **kwargs) -> DaskMeshes:
    """`splinegpu.Context.ribbons` on a dask.array or dask.bag of curves, as `strokes`."""
    return _meshes("ribbons", curves, backend, kwargs)


def _closest_block(queries, curves, kind: str, backend: str, kwargs: dict[str, Any]):
    """One block of query points answered: (curve, t, point..., distance) per row, float64
    (a curve index is exact in float64 far past any batch's size)."""
    r = worker_context(backend).closest(curves, kind, queries, **kwargs)
    return np.column_stack([r.curve.astype(np.float64), r.t, r.point, r.distance])


class DaskClosestPoints:
    """`splinegpu.ClosestPoints`' arrays as dask arrays, chunked as the query points were:
    curve (int64), t, point (Q, D) and distance."""

    def __init__(self, curve, t, point, distance):
        self.curve, self.t, self.point, self.distance = curve, t, point, distance

    def compute(self) -> splinegpu.ClosestPoints:
        """Everything, gathered into one `splinegpu.ClosestPoints` in this process."""
        import dask

        names = ("curve", "t", "point", "distance")
        arrays = dask.compute(*(getattr(self, name) for name in names))
        return splinegpu.ClosestPoints(dict(zip(names, arrays)))


def closest(curves, kind: str = "catmull-rom", points=None, *, backend: str = "auto",
            **kwargs) -> DaskClosestPoints:
    """`splinegpu.Context.closest` for a dask.array of query points (Q, D), chunked along its
    rows: every block answered on the cluster against the same curves (a NumPy batch, as
    `Context.closest` takes it, sent to each block's task), `kwargs` the kind's fields."""
    import dask.array as da

    if not isinstance(points, da.Array) or points.ndim != 2:
        raise TypeError(f"points: must be a 2-D dask.array of query points, got "
                        f"{type(points).__name__}")
    dim = points.shape[1]
    points = points.rechunk({1: dim}).astype(np.float64)
    packed = points.map_blocks(_closest_block, curves, kind, backend, kwargs,
                               chunks=(points.chunks[0], (dim + 3,)), dtype=np.float64)
    return DaskClosestPoints(packed[:, 0].astype(np.int64), packed[:, 1],
                             packed[:, 2:2 + dim], packed[:, 2 + dim])


def _persisted(curves, block, *args):
    """The partitions of `curves` (a dask.array (C, n, D) chunked along its first axis only,
    or a dask.bag) made by `block(partition, *args)` on the workers and kept there, and each
    one's arrays' shapes and types (small, gathered here)."""
    import dask
    import dask.array as da

    if isinstance(curves, da.Array):
        if curves.ndim != 3:
            raise ValueError(f"curves: must be a (C, n, D) dask array, got shape {curves.shape}")
        if len(curves.chunks[1]) != 1 or len(curves.chunks[2]) != 1:
            raise ValueError("curves: chunk along the first axis only (whole curves per block)")
        partitions = curves.to_delayed().ravel().tolist()
    else:
        partitions = curves.to_delayed()
    parts = dask.persist(*[dask.delayed(block)(p, *args) for p in partitions])
    meta = dask.compute(*[dask.delayed(_meta)(p) for p in parts])
    return parts, meta


def _concatenated(parts, meta, index: int, starts=None):
    """Array `index` of every partition as one dask array (None where the partitions hold
    None there), each partition's values plus its entry of `starts` where given."""
    import dask
    import dask.array as da

    blocks = []
    for k, (p, m) in enumerate(zip(parts, meta)):
        shape, dtype = m["shapes"][index], m["dtypes"][index]
        if shape is None:
            return None
        item = dask.delayed(_item)(p, index) if starts is None else \
            dask.delayed(_plus)(p, index, int(starts[k]))
        blocks.append(da.from_delayed(item, shape=shape, dtype=dtype))
    return da.concatenate(blocks) if blocks else None


def _offsets(parts, meta, index: int, rows_of: int):
    """Offsets array `index` of every partition stitched into the whole batch's: each
    partition's but its last, moved by the rows of array `rows_of` before it, then the total."""
    import dask
    import dask.array as da

    starts = np.concatenate([[0], np.cumsum([m["shapes"][rows_of][0] for m in meta])])
    offsets = [
        da.from_delayed(dask.delayed(_shifted)(p, index, int(start)),
                        shape=(m["shapes"][index][0] - 1,), dtype=np.int64)
        for p, m, start in zip(parts, meta, starts[:-1])
    ]
    offsets.append(da.from_array(np.array([starts[-1]], dtype=np.int64)))
    return da.concatenate(offsets)


def _meta(part):
    shapes = [None if a is None else a.shape for a in part]
    dtypes = [None if a is None else a.dtype for a in part]
    return {"shapes": shapes, "dtypes": dtypes}


def _item(part, index):
    return part[index]


def _plus(part, index, start):
    return part[index] + start


def _shifted(part, index, start):
    """A partition's offsets (array `index`) but its last, moved to the batch's rows."""
    return part[index][:-1] + start
