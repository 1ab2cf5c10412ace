"""`python -m splinegpu.bench [--workers]`: the package against the crate and against SciPy, on the
CPU backend, in one run on the same inputs; each figure the fastest of 5 after a warm-up.

- w1: 10,000 Catmull-Rom curves (34 points in 3-D, 32 samples per segment: 9.93 M samples)
  through `ctx.tessellate(..., out=reused)`, against the crate's own path on the same curves
  from Rust in this process (fit + job + evaluate_into, f64 with t): the package's overhead.
- fit-1m: `CubicSpline(x, y, bc_type="natural")` on 1,000,000 uneven knots in 3-D, ours vs SciPy.
- eval-at: 10,000 natural splines of 64 uneven knots in 3-D at 1,000 random unsorted x each:
  our batched `CubicSplines` + evaluation against SciPy's loop of CubicSpline + __call__.
- w1 against SciPy's CubicHermiteSpline batched over columns (Catmull-Rom tangents), the same
  9.93 M samples.
With --workers: 1 against 2 Dask worker processes (LocalCluster) on w1's curves x 4.
"""

from __future__ import annotations

import sys
import time

import numpy as np

import splinegpu
from splinegpu import _native

REPEATS = 5


def best(run, repeats=REPEATS):
    run()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return min(times)


def w1_curves(count=10_000):
    return np.random.default_rng(1).uniform(-100, 100, (count, 34, 3))


def main(argv):
    ctx = splinegpu.Context("cpu")
    rows = []
    curves = w1_curves()
    first = ctx.tessellate(curves, "catmull-rom", per_segment=32)
    ours = best(lambda: ctx.tessellate(curves, "catmull-rom", per_segment=32, out=first))
    rust_whole, rust_eval = _native.time_rust_tessellate(curves, "catmull-rom", 32, REPEATS)
    rows.append(("w1 tessellate(out=reused)", ours, "crate from Rust (fit+job+evaluate)",
                 rust_whole, f"overhead {100 * (ours / rust_whole - 1):+.1f} %"))
    rows.append(("  of which evaluate_into", rust_eval, "", float("nan"), ""))

    from scipy.interpolate import CubicHermiteSpline, CubicSpline

    rng = np.random.default_rng(2)
    x = np.concatenate([[0.0], np.cumsum(10 ** rng.uniform(-1, 1, 999_999))])
    y = rng.uniform(-10, 10, (1_000_000, 3))
    ours = best(lambda: splinegpu.CubicSpline(x, y, bc_type="natural"))
    theirs = best(lambda: CubicSpline(x, y, bc_type="natural"))
    rows.append(("fit-1m CubicSpline natural", ours, "SciPy CubicSpline", theirs,
                 f"{theirs / ours:.1f}x (goal >= 8x)"))

    rng = np.random.default_rng(3)
    xs = np.concatenate([np.zeros((10_000, 1)),
                         np.cumsum(rng.uniform(0.1, 2.0, (10_000, 63)), axis=1)], axis=1)
    ys = rng.uniform(-10, 10, (10_000, 64, 3))
    qs = rng.uniform(0, 1, (10_000, 1000)) * xs[:, -1:]

    def ours_at():
        splinegpu.CubicSplines(xs, ys, bc_type="natural")(qs)

    def scipy_at():
        for k, v, q in zip(xs, ys, qs):
            CubicSpline(k, v, bc_type="natural")(q)

    ours = best(ours_at)
    theirs = best(scipy_at, repeats=1)
    rows.append(("eval-at CubicSplines batch", ours, "SciPy loop (1 run)", theirs,
                 f"{theirs / ours:.1f}x (goal >= 30x)"))

    # Catmull-Rom on "control" ends: segment i runs from P[i+1] to P[i+2] with tangents
    # (P[i+2] - P[i]) / 2; all curves as columns of one CubicHermiteSpline.
    n = curves.shape[1]
    knots = np.arange(n - 2, dtype=np.float64)
    columns = curves.transpose(1, 0, 2).reshape(n, -1)
    at = np.concatenate([np.repeat(np.arange(n - 3), 32) + np.tile(np.arange(32) / 32, n - 3),
                         [n - 3.0]])

    def scipy_w1():
        spline = CubicHermiteSpline(knots, columns[1:-1], (columns[2:] - columns[:-2]) / 2)
        spline(at)

    ours = best(lambda: ctx.tessellate(curves, "catmull-rom", per_segment=32, out=first))
    theirs = best(scipy_w1)
    rows.append(("w1 tessellate", ours, "SciPy CubicHermiteSpline", theirs,
                 f"{theirs / ours:.1f}x"))

    if "--workers" in argv:
        rows.extend(workers())

    print(f"splinegpu.bench on {ctx.info}; fastest of {REPEATS} after a warm-up\n")
    print(f"| {'ours':<28} | {'s':>8} | {'against':<36} | {'s':>8} | ratio |")
    print(f"|{'-' * 30}|{'-' * 10}|{'-' * 38}|{'-' * 10}|---|")
    for name, a, other, b, ratio in rows:
        print(f"| {name:<28} | {a:8.4f} | {other:<36} | {b:8.4f} | {ratio} |")


def workers():
    """w1's curves x 4 on 1 and on 2 Dask worker processes of one thread each."""
    import warnings

    import dask.array as da
    from distributed import Client, LocalCluster

    # The curves travel inside the graph (they are made here, not on the workers): expected.
    warnings.filterwarnings("ignore", message="Sending large graph")

    import splinegpu.dask

    curves = w1_curves(40_000)
    seconds = {}
    for n in (1, 2):
        with LocalCluster(n_workers=n, processes=True, threads_per_worker=1, host="127.0.0.1",
                          dashboard_address=None) as cluster, Client(cluster):
            lazy = da.from_array(curves, chunks=(2_500, 34, 3))

            def run(lazy=lazy):
                splinegpu.dask.tessellate(lazy, backend="cpu", kind="catmull-rom",
                                          per_segment=32).points.sum().compute()

            seconds[n] = best(run, repeats=3)
    return [("Dask 2 workers (w1 x 4)", seconds[2], "Dask 1 worker", seconds[1],
             f"{seconds[1] / seconds[2]:.2f}x")]


if __name__ == "__main__":
    main(sys.argv[1:])
