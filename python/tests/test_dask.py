"""splinegpu.dask on a distributed.LocalCluster of two worker processes on loopback: the
distributed result equals the single-process one bit for bit on 10,000 curves, with real chunk
sizes and stitched curve offsets; a worker killed mid-run is retried by Dask and the result is
still complete and equal."""

import os
import signal
import threading
import time

import dask.array as da
import dask.bag as db
import numpy as np
import pytest
from distributed import Client, LocalCluster

import splinegpu
import splinegpu.dask

KW = {"kind": "bspline", "per_segment": 8, "derivatives": 1}


@pytest.fixture(scope="module")
def client():
    with LocalCluster(n_workers=2, processes=True, threads_per_worker=1, host="127.0.0.1",
                      dashboard_address=None) as cluster, Client(cluster) as client:
        yield client


@pytest.fixture(scope="module")
def curves():
    return np.random.default_rng(0).uniform(-1, 1, (10_000, 12, 3))


@pytest.fixture(scope="module")
def single(curves):
    return splinegpu.Context("cpu").tessellate(curves, **KW)


def assert_equal(got, want):
    for key in ("t", "points", "d1", "curve_offsets"):
        np.testing.assert_array_equal(getattr(got, key), getattr(want, key), err_msg=key)
    assert got.d2 is None and want.d2 is None


def test_array_partitions_equal_one_process(client, curves, single):
    lazy = splinegpu.dask.tessellate(da.from_array(curves, chunks=(1000, 12, 3)), backend="cpu",
                                     **KW)
    # 9 segments of 8 samples plus the end point per curve: chunk sizes known exactly.
    assert lazy.points.chunks[0] == (1000 * 73,) * 10
    assert lazy.curve_offsets.shape == (10_001,)
    assert_equal(lazy.compute(), single)
    # A slice reads only the partitions it needs.
    np.testing.assert_array_equal(lazy.points[5000:5100].compute(), single.points[5000:5100])


def test_bag_of_ragged_curves(client):
    rng = np.random.default_rng(1)
    ragged = [rng.uniform(-1, 1, (int(n), 2)) for n in rng.integers(4, 30, 500)]
    want = splinegpu.Context("cpu").tessellate(ragged, kind="natural", arc_length=20)
    lazy = splinegpu.dask.tessellate(db.from_sequence(ragged, npartitions=7), backend="cpu",
                                     kind="natural", arc_length=20)
    got = lazy.compute()
    np.testing.assert_array_equal(got.points, want.points)
    np.testing.assert_array_equal(got.curve_offsets, want.curve_offsets)


def test_meshes_by_partition_equal_one_process(client, curves):
    cpu = splinegpu.Context("cpu")
    kw = {"kind": "catmull-rom", "ends": "closed", "radius": 0.05, "sides": 6, "per_segment": 4}
    want = cpu.tubes(curves[:2000], **kw)
    lazy = splinegpu.dask.tubes(da.from_array(curves[:2000], chunks=(700, 12, 3)),
                                backend="cpu", **kw)
    # One mesh chunk per partition: 12 segments of 4 rings of 6 (closed: the last is the first).
    assert lazy.points.chunks[0] == (700 * 288, 700 * 288, 600 * 288)
    got = lazy.compute()
    for name, array in want.arrays().items():
        np.testing.assert_array_equal(getattr(got, name), array, err_msg=name)
    rng = np.random.default_rng(2)
    ragged = [rng.uniform(-1, 1, (int(n), 2)) for n in rng.integers(4, 20, 300)]
    kw = {"kind": "natural", "width": 0.02, "join": "round", "dash": [0.3, 0.1],
          "arc_length": 30}
    want = cpu.strokes(ragged, **kw)
    got = splinegpu.dask.strokes(db.from_sequence(ragged, npartitions=5), backend="cpu",
                                 **kw).compute()
    assert got.normals is None
    for name, array in want.arrays().items():
        np.testing.assert_array_equal(getattr(got, name), array, err_msg=name)


def test_a_killed_worker_is_retried(client, curves, single):
    victim = sorted(client.scheduler_info()["workers"])[0]
    # The worker process of this test's own cluster, killed hard from here.
    pid = client.run(os.getpid, workers=[victim])[victim]

    def kill_soon():
        time.sleep(0.05)
        os.kill(pid, signal.SIGKILL)

    killer = threading.Thread(target=kill_soon)
    killer.start()
    lazy = splinegpu.dask.tessellate(da.from_array(curves, chunks=(250, 12, 3)), backend="cpu",
                                     **KW)
    killer.join()
    # Whatever the killed worker held is computed again: nothing lost, nothing doubled.
    assert_equal(lazy.compute(), single)
    # The kill happened (its nanny started a new worker at another address).
    client.wait_for_workers(2, timeout=30)
    assert victim not in client.scheduler_info()["workers"]


def test_a_spline_travels_to_a_worker_and_answers_as_scipy(client):
    # client.submit pickles the spline (its tables, bit for bit, and its context as "cpu").
    from scipy.interpolate import CubicSpline

    rng = np.random.default_rng(5)
    x = np.cumsum(10 ** rng.uniform(-1, 1, 30))
    y = rng.uniform(-1, 1, (30, 2))
    q = rng.uniform(x[0] - 1, x[-1] + 1, 200)
    spline = splinegpu.CubicSpline(x, y, bc_type="natural", context=splinegpu.Context("cpu"))
    got = client.submit(lambda s, q: s(q, 1), spline, q).result()
    np.testing.assert_array_equal(got, spline(q, 1))
    np.testing.assert_allclose(got, CubicSpline(x, y, bc_type="natural")(q, 1), rtol=0,
                               atol=1e-12 * np.abs(got).max())


def test_closest_points_by_block_equal_one_process(client):
    rng = np.random.default_rng(3)
    curves = rng.uniform(-1, 1, (50, 8, 2))
    queries = rng.uniform(-1.5, 1.5, (5_000, 2))
    want = splinegpu.Context("cpu").closest(curves, "catmull-rom", queries)
    got = splinegpu.dask.closest(curves, "catmull-rom", da.from_array(queries, chunks=(700, 2)),
                                 backend="cpu").compute()
    for name in ("curve", "t", "point", "distance"):
        np.testing.assert_array_equal(getattr(got, name), getattr(want, name))
    assert got.curve.dtype == np.int64
    with pytest.raises(TypeError, match=r"points: must be a 2-D dask\.array"):
        splinegpu.dask.closest(curves, "catmull-rom", queries)
