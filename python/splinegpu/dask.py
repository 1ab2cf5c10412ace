"""Tessellating more curves than one machine holds, on a Dask cluster.

    >>> from distributed import Client
    >>> import dask.array as da, splinegpu.dask
    >>> client = Client("scheduler:8786")                 # or LocalCluster()
    >>> curves = da.random.uniform(-1, 1, (10**8, 16, 3), chunks=(10**6, 16, 3))
    >>> r = splinegpu.dask.tessellate(curves, kind="bspline", per_segment=32)
    >>> r.points                                          # dask array, exact chunk sizes
    >>> r.points[:1000].compute()

Each partition (a block of whole curves of a dask.array, or a partition of a dask.bag of (n_i, D)
arrays) is tessellated by the package in its worker, on one `Context` per worker process made
once. Curves are independent, so throughput grows with workers. The partitions are computed once
and kept on the workers (`persist`); the result's dask arrays (t, points, d1, d2) have their real
chunk sizes, and `curve_offsets` is stitched across partitions into offsets of the whole batch.
A worker lost mid-run is handled by Dask: its partitions are computed again elsewhere.
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
    parts = [dask.delayed(_block)(p, backend, kwargs) for p in partitions]
    parts = dask.persist(*parts)
    # Sizes and types of each partition's arrays: small, gathered here.
    meta = dask.compute(*[dask.delayed(_meta)(p) for p in parts])
    starts = np.concatenate([[0], np.cumsum([m["rows"] for m in meta])])
    # The partitions as delayed tuples again (persisted), one getter per array.
    arrays: list[Any] = []
    for index in range(4):
        blocks = []
        for p, m in zip(parts, meta):
            shape, dtype = m["shapes"][index], m["dtypes"][index]
            if shape is None:
                break
            blocks.append(da.from_delayed(dask.delayed(_item)(p, index), shape=shape, dtype=dtype))
        arrays.append(da.concatenate(blocks) if len(blocks) == len(parts) and blocks else None)
    offsets = [
        da.from_delayed(dask.delayed(_shifted)(p, int(start)), shape=(m["curves"],),
                        dtype=np.int64)
        for p, m, start in zip(parts, meta, starts[:-1])
    ]
    offsets.append(da.from_array(np.array([starts[-1]], dtype=np.int64)))
    t, points, d1, d2 = arrays
    return DaskTessellation(t, points, d1, d2, da.concatenate(offsets))


def _meta(part):
    shapes = [None if a is None else a.shape for a in part[:4]]
    dtypes = [None if a is None else a.dtype for a in part[:4]]
    return {"rows": len(part[0]), "curves": len(part[4]) - 1, "shapes": shapes, "dtypes": dtypes}


def _item(part, index):
    return part[index]


def _shifted(part, start):
    """A partition's curve offsets but its last, moved to the batch's rows."""
    return part[4][:-1] + start
