"""`python python/benches/bench.py [--workers | --gridded | --fitting]`: the package against SciPy
(and against the crate from Rust), on the CPU backend, in one run on the same inputs; each
figure the fastest of 5 after a warm-up (a call of microseconds: the fastest of 5 loops of many
calls, per call). Every timed call is the whole call as it is made: arguments converted, points
located, results allocated.

- s(x) on one spline: one point on 100 and on 1,000,000 knots (the cost per call must not
  grow with the knots), 1,000 random points on 1,000 knots, 10 M sorted points on 1 M knots
  in 3-D; on 101 knots, what SciPy answers through PPoly: a call at one x past the knots, the
  antiderivative, a derivative made and called at one x, an integral; a BSpline of 1,000
  knots at one point and at 1,000,000.
- CubicSplines: 10,000 natural splines of 64 uneven knots in 3-D, fitted (against SciPy's loop
  of CubicSpline constructions) and called at 1,000 unsorted x each (against SciPy's loop of
  calls on splines already made).
- fit-1m: `CubicSpline(x, y, bc_type="natural")` on 1,000,000 uneven knots in 3-D.
- splinegpu.interpolate's batches (CubicSplines, CubicHermiteSplines, PchipInterpolators,
  Akima1DInterpolators, make_interp_splines, BSplines from knots and coefficients): the same
  10,000 splines made and called at their 1,000 x, against SciPy's loop of the single
  classes; and the roots and the integrals of 10,000 1-D splines, one batch against SciPy's
  loop.
- tessellate: one curve of 16 points (32 samples per segment), and w1 (10,000 Catmull-Rom
  curves of 34 points in 3-D, 9.93 M samples) with a fresh result and with `out=`, against
  SciPy's CubicHermiteSpline with Catmull-Rom tangents on the same curves, and against the
  crate's own whole call from Rust (`splinegpu bench --workload w1`'s cpu-whole, run by this
  bench when the command line is built: the package's overhead).
- nurbs: w1's curves as clamped NURBS with weights (w1-nurbs) against w1 in the same run, and
  100 of them against geomdl's NURBS curves on the same parameters (`pip install geomdl`).
- gridded data (bench_gridded.py): RegularGridInterpolator, NdBSpline and their batches.
- fitting noisy data (bench_fitting.py): smoothing (GCV), FITPACK and least-squares fits and
  their batches.
With --workers: 1 against 2 Dask worker processes (LocalCluster) on w1's curves x 4; with
--gridded or --fitting: those rows alone.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import bench_fitting
import bench_gridded
import numpy as np
from timing import REPEATS, best, faster

import splinegpu


def w1_curves(count=10_000):
    return np.random.default_rng(1).uniform(-100, 100, (count, 34, 3))


def uneven_knots(rng, n):
    return np.concatenate([[0.0], np.cumsum(10 ** rng.uniform(-1, 1, n - 1))])



def main(argv):
    ctx = splinegpu.Context("cpu")
    alone = "--gridded" in argv or "--fitting" in argv
    rows = [] if alone else curves_and_1d(ctx)
    if "--workers" in argv:
        rows.extend(workers())
    if "--fitting" not in argv:
        try:
            gpu = splinegpu.Context("gpu")
        except RuntimeError:
            gpu = None
        rows.extend(bench_gridded.rows(gpu))
    if "--gridded" not in argv:
        rows.extend(bench_fitting.rows())
    print(f"python/benches/bench.py on {ctx.info}; fastest of {REPEATS} after a warm-up\n")
    print(f"| {'ours':<38} | {'seconds':>10} | {'against':<26} | {'seconds':>10} | ratio |")
    print(f"|{'-' * 40}|{'-' * 12}|{'-' * 28}|{'-' * 12}|---|")
    for name, a, other, b, ratio in rows:
        print(f"| {name:<38} | {a:10.3g} | {other:<26} | {b:10.3g} | {ratio} |")


def curves_and_1d(ctx):
    """The rows of the curves and the 1-D classes (all but the gridded ones)."""
    from scipy.interpolate import CubicHermiteSpline, CubicSpline

    rows = []
    rng = np.random.default_rng(4)

    one_point = {}
    for knots in (100, 1_000_000):
        x = uneven_knots(rng, knots)
        y = rng.uniform(-10, 10, knots)
        ours, theirs = splinegpu.CubicSpline(x, y), CubicSpline(x, y)
        q = np.array([x[-1] * 0.37])
        a = best(lambda s=ours, q=q: s(q), calls=2000)
        b = best(lambda s=theirs, q=q: s(q), calls=2000)
        one_point[knots] = a
        rows.append((f"s(x), {knots:,} knots, 1 point", a, "SciPy", b, faster(a, b, ">= 1x")))
    rows.append(("  1 M knots / 100 knots", one_point[1_000_000], "", one_point[100],
                 f"{one_point[1_000_000] / one_point[100]:.2f} (goal <= 1.5)"))

    # What SciPy answers through PPoly on a spline of 101 knots: a call at one x past the
    # knots, the antiderivative, a derivative called at one x, an integral.
    x = uneven_knots(rng, 101)
    y = rng.uniform(-10, 10, 101)
    ours, theirs = splinegpu.CubicSpline(x, y), CubicSpline(x, y)
    past = np.array([x[-1] * 1.2])
    for label, call in (("s(x), 101 knots, 1 point past them", lambda s: s(past)),
                        ("s.antiderivative(), 101 knots", lambda s: s.antiderivative()),
                        ("s.derivative()(x), 101 knots, 1 point",
                         lambda s: s.derivative()(past)),
                        ("s.integrate(a, b), 101 knots", lambda s: s.integrate(1.0, x[-1]))):
        a = best(lambda c=call: c(ours), calls=2000)
        b = best(lambda c=call: c(theirs), calls=2000)
        rows.append((label, a, "SciPy", b, faster(a, b, ">= 1x")))

    # A BSpline (SciPy's knots and coefficients, de Boor's sums on the CPU as SciPy's): one
    # point, and 1,000,000 random points, on 1,000 knots.
    from scipy.interpolate import BSpline, make_interp_spline

    x = uneven_knots(rng, 1000)
    fitted = make_interp_spline(x, rng.uniform(-10, 10, 1000))
    ours, theirs = splinegpu.interpolate.BSpline(*fitted.tck), BSpline(*fitted.tck)
    for label, q, calls in (("1 point", np.array([x[-1] * 0.37]), 2000),
                            ("1,000,000 points", rng.uniform(0, x[-1], 1_000_000), 1)):
        a = best(lambda q=q: ours(q), calls=calls)
        b = best(lambda q=q: theirs(q), calls=calls)
        rows.append((f"BSpline(t, c, 3)(x), 1,000 knots, {label}", a, "SciPy", b,
                     faster(a, b, ">= 1x")))

    x = uneven_knots(rng, 1000)
    y = rng.uniform(-10, 10, 1000)
    q = rng.uniform(0, x[-1], 1000)
    ours, theirs = splinegpu.CubicSpline(x, y), CubicSpline(x, y)
    a, b = best(lambda: ours(q), calls=200), best(lambda: theirs(q), calls=200)
    rows.append(("s(x), 1,000 knots, 1,000 points", a, "SciPy", b, faster(a, b, ">= 2x")))

    x = uneven_knots(rng, 1_000_000)
    y = rng.uniform(-10, 10, (1_000_000, 3))
    q = np.sort(rng.uniform(0, x[-1], 10_000_000))
    ours, theirs = splinegpu.CubicSpline(x, y), CubicSpline(x, y)
    a, b = best(lambda: ours(q)), best(lambda: theirs(q), repeats=2)
    rows.append(("s(x), 1 M knots 3-D, 10 M sorted", a, "SciPy", b, faster(a, b, ">= 3x")))
    a = best(lambda: splinegpu.CubicSpline(x, y, bc_type="natural"))
    b = best(lambda: CubicSpline(x, y, bc_type="natural"), repeats=2)
    rows.append(("CubicSpline fit, 1 M knots 3-D", a, "SciPy", b, faster(a, b, ">= 5x")))

    xs = np.concatenate([np.zeros((10_000, 1)),
                         np.cumsum(rng.uniform(0.1, 2.0, (10_000, 63)), axis=1)], axis=1)
    ys = rng.uniform(-10, 10, (10_000, 64, 3))
    qs = rng.uniform(0, 1, (10_000, 1000)) * xs[:, -1:]
    a = best(lambda: splinegpu.CubicSplines(xs, ys, bc_type="natural"))
    b = best(lambda: [CubicSpline(k, v, bc_type="natural") for k, v in zip(xs, ys)], repeats=1)
    rows.append(("CubicSplines fit, 10,000 x 64", a, "SciPy loop (1 run)", b,
                 faster(a, b, ">= 20x")))
    batch = splinegpu.CubicSplines(xs, ys, bc_type="natural")
    splines = [CubicSpline(k, v, bc_type="natural") for k, v in zip(xs, ys)]
    a = best(lambda: batch(qs))
    b = best(lambda: [s(q) for s, q in zip(splines, qs)], repeats=2)
    rows.append(("CubicSplines call, 10,000 x 1,000", a, "SciPy loop", b,
                 faster(a, b, ">= 6x")))

    rows.extend(batches(xs, ys, qs))

    small = np.random.default_rng(5).uniform(-100, 100, (1, 16, 3))
    a = best(lambda: ctx.tessellate(small, "catmull-rom", per_segment=32), calls=500)
    knots16, cols16, at16 = _hermite_inputs(small, 32)
    b = best(lambda: CubicHermiteSpline(knots16, cols16[1:-1],
                                        (cols16[2:] - cols16[:-2]) / 2)(at16), calls=500)
    rows.append(("tessellate, 1 curve x 16 points", a, "SciPy CubicHermiteSpline", b,
                 faster(a, b)))

    curves = w1_curves()
    knots, columns, at = _hermite_inputs(curves, 32)

    def scipy_w1():
        CubicHermiteSpline(knots, columns[1:-1], (columns[2:] - columns[:-2]) / 2)(at)

    theirs = best(scipy_w1)
    fresh = best(lambda: ctx.tessellate(curves, "catmull-rom", per_segment=32))
    first = ctx.tessellate(curves, "catmull-rom", per_segment=32)
    reused = best(lambda: ctx.tessellate(curves, "catmull-rom", per_segment=32, out=first))
    rows.append(("w1 tessellate, fresh result", fresh, "SciPy CubicHermiteSpline", theirs,
                 faster(fresh, theirs, ">= 3x")))
    rows.append(("w1 tessellate(out=reused)", reused, "fresh result", fresh,
                 f"fresh / out= {fresh / reused:.2f} (goal <= 1.5)"))
    crate = crate_w1()
    if crate is None:
        print("  the crate from Rust: skipped (no splinegpu binary: cargo build --release "
              "-p splinegpu-cli, or set SPLINEGPU)", file=sys.stderr)
    else:
        rust_whole, rust_eval = crate
        rows.append(("  the crate from Rust", rust_whole, "of which evaluate_into", rust_eval,
                     f"out= overhead {100 * (reused / rust_whole - 1):+.1f} %"))

    rows.extend(nurbs(ctx, fresh))
    return rows


def crate_w1():
    """The crate's own whole call on w1 (`splinegpu bench --workload w1`'s cpu-whole: fitted
    and planned on every thread, evaluated in f64 with t into reused memory) and its f64
    evaluation alone (cpu-all f64), the fastest of its runs, in seconds; None without the
    command line. Its w1 is the contract's (10,000 curves of 34 points in ±100, its own
    seeded draw): the same work as this bench's w1, other numbers."""
    binary = os.environ.get("SPLINEGPU") or shutil.which(
        "splinegpu", path=str(Path(__file__).resolve().parents[2] / "target" / "release"))
    if binary is None:
        binary = shutil.which("splinegpu")
    if binary is None:
        return None
    env = dict(os.environ, VK_ICD_FILENAMES="/nonexistent")  # the CPU paths only
    done = subprocess.run([binary, "bench", "--workload", "w1", "--json"], env=env,
                          capture_output=True, text=True, check=True)
    found = {}
    for line in done.stdout.splitlines():
        row = json.loads(line)
        found[(row["path"], row.get("float"))] = row["min_seconds"]
    return found[("cpu-whole", "f64")], found[("cpu-all", "f64")]


def batches(xs, ys, qs):
    """The batched classes of splinegpu.interpolate on 10,000 splines of 64 uneven knots in
    3-D, each made and called at its own 1,000 unsorted x (construction and evaluation, as
    a caller pays them), against SciPy's loop of the single class doing the same (1 run)."""
    import scipy.interpolate as scipy

    import splinegpu.interpolate as si

    dydxs = np.random.default_rng(6).uniform(-1, 1, ys.shape)
    # B-splines given by their knots and coefficients (SciPy's own interpolants').
    tcks = [(s.t, s.c) for s in (scipy.make_interp_spline(k, v) for k, v in zip(xs, ys))]
    ts, cs = [t for t, _ in tcks], [c for _, c in tcks]
    cases = [
        ("CubicSplines (not-a-knot)", lambda ctx: si.CubicSplines(xs, ys, context=ctx),
         lambda k, v, d, tck: scipy.CubicSpline(k, v)),
        ("CubicHermiteSplines", lambda ctx: si.CubicHermiteSplines(xs, ys, dydxs, context=ctx),
         lambda k, v, d, tck: scipy.CubicHermiteSpline(k, v, d)),
        ("PchipInterpolators", lambda ctx: si.PchipInterpolators(xs, ys, context=ctx),
         lambda k, v, d, tck: scipy.PchipInterpolator(k, v)),
        ("Akima1DInterpolators (makima)",
         lambda ctx: si.Akima1DInterpolators(xs, ys, method="makima", context=ctx),
         lambda k, v, d, tck: scipy.Akima1DInterpolator(k, v, method="makima")),
        ("make_interp_splines (not-a-knot)",
         lambda ctx: si.make_interp_splines(xs, ys, context=ctx),
         lambda k, v, d, tck: scipy.make_interp_spline(k, v)),
        ("BSplines(t, c)", lambda ctx: si.BSplines(ts, cs, context=ctx),
         lambda k, v, d, tck: scipy.BSpline(*tck, 3)),
    ]
    try:
        gpu = splinegpu.Context("gpu")
    except RuntimeError:
        gpu = None
    rows = []
    for name, ours, theirs in cases:
        a = best(lambda ours=ours: ours(None)(qs))
        b = best(lambda theirs=theirs: [theirs(k, v, d, tck)(q) for k, v, d, tck, q
                                        in zip(xs, ys, dydxs, tcks, qs)], repeats=1)
        rows.append((f"{name} make + call", a, "SciPy loop (1 run)", b, faster(a, b, ">= 10x")))
        if gpu is not None:
            g = best(lambda ours=ours: ours(gpu)(qs), repeats=2)
            adapter = gpu.info.removeprefix("gpu: ").split(" (")[0]
            rows.append((f"  the same on the GPU backend ({adapter})", g,
                         "CPU backend", a, faster(g, a)))
    # Roots and integrals of 10,000 1-D splines already made: ours in one batch, SciPy's one
    # by one.
    ours = si.CubicSplines(xs, ys[:, :, :1])
    theirs = [scipy.CubicSpline(k, v[:, 0]) for k, v in zip(xs, ys)]
    a = best(ours.roots)
    b = best(lambda: [s.roots() for s in theirs], repeats=1)
    rows.append(("CubicSplines.roots, 10,000 1-D", a, "SciPy loop (1 run)", b,
                 faster(a, b, ">= 10x")))
    lo, hi = xs[:, 5] + 0.5, xs[:, -3] - 0.5
    a = best(lambda: ours.integrate(lo, hi))
    b = best(lambda: [s.integrate(p, q) for s, p, q in zip(theirs, lo, hi)], repeats=1)
    rows.append(("CubicSplines.integrate, 10,000 1-D", a, "SciPy loop (1 run)", b,
                 faster(a, b)))
    return rows


def w1_nurbs(count):
    """w1's points as clamped NURBS, as `splinegpu bench`'s w1-nurbs makes them: knots 0 four
    times, 30 interior knots with spacings 10^U(-1, 1), the end four times (scaled to [0, 1],
    which geomdl requires), weights in [0.5, 2]."""
    rng = np.random.default_rng(3)
    spacings = 10 ** rng.uniform(-1, 1, (count, 31))
    inner = np.cumsum(spacings, axis=1)
    inner /= inner[:, -1:]
    knots = np.concatenate([np.zeros((count, 4)), inner[:, :30], np.ones((count, 4))], axis=1)
    return w1_curves(count), knots, rng.uniform(0.5, 2.0, (count, 34))


def nurbs(ctx, w1_fresh):
    """Weighted NURBS: w1-nurbs (10,000 curves, 32 samples per span) against w1 in this run,
    and 100 of its curves against geomdl (pure Python, the NURBS package of PyPI most used
    without a CAD kernel) on the same parameters, after checking that the two agree."""
    curves, knots, weights = w1_nurbs(10_000)

    def ours(n):
        return ctx.tessellate(curves[:n], "nurbs", knots=knots[:n], weights=weights[:n],
                              per_segment=32)

    whole = best(lambda: ours(10_000))
    rows = [("w1-nurbs tessellate, fresh result", whole, "w1 (Catmull-Rom)", w1_fresh,
             f"{whole / w1_fresh:.2f}x w1's time (goal <= 1.5)")]
    try:
        from geomdl import NURBS
    except ImportError:
        return [*rows, ("nurbs vs geomdl: not installed", 0.0, "pip install geomdl", 0.0, "")]

    n = 100
    result = ours(n)
    offsets = result.curve_offsets

    def theirs():
        points = []
        for i in range(n):
            curve = NURBS.Curve()
            curve.degree = 3
            curve.ctrlpts = curves[i].tolist()
            curve.weights = weights[i].tolist()
            curve.knotvector = knots[i].tolist()
            points.append(curve.evaluate_list(result.t[offsets[i]:offsets[i + 1]].tolist()))
        return points

    worst = np.abs(np.concatenate(theirs()) - result.points).max()
    if worst > 1e-9:
        raise AssertionError(f"geomdl and splinegpu differ by {worst:.3g} on w1-nurbs")
    a, b = best(lambda: ours(n)), best(theirs, repeats=1)
    return [*rows, (f"nurbs, {n} curves ({offsets[-1]:,} samples)", a,
                    "geomdl loop (same t; 1 run)", b, faster(a, b))]


def _hermite_inputs(curves, k):
    """Catmull-Rom on "control" ends as SciPy's CubicHermiteSpline sees it: segment i runs from
    P[i+1] to P[i+2] with tangents (P[i+2] - P[i]) / 2; all curves as columns of one spline,
    evaluated at k points per segment and the end."""
    n = curves.shape[1]
    knots = np.arange(n - 2, dtype=np.float64)
    columns = curves.transpose(1, 0, 2).reshape(n, -1)
    at = np.concatenate([np.repeat(np.arange(n - 3), k) + np.tile(np.arange(k) / k, n - 3),
                         [n - 3.0]])
    return knots, columns, at


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
