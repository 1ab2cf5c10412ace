"""Tessellate a million curves on a Dask cluster (here a LocalCluster of 2 worker processes).

    python python/examples/dask_tessellate.py [SCHEDULER_ADDRESS]
"""

import sys

import dask.array as da
from distributed import Client, LocalCluster

import splinegpu.dask

if __name__ == "__main__":
    cluster = sys.argv[1] if len(sys.argv) > 1 else LocalCluster(n_workers=2)
    client = Client(cluster)
    curves = da.random.uniform(-1, 1, (1_000_000, 16, 3), chunks=(50_000, 16, 3))
    result = splinegpu.dask.tessellate(curves, kind="bspline", per_segment=16)
    print(result.points)  # a dask array with its real chunk sizes
    print("first curve:", result.points[: result.curve_offsets[1].compute()].compute()[:3])
    print("extent:", result.points.min(axis=0).compute(), result.points.max(axis=0).compute())
    client.close()
