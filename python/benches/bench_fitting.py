"""The fitting rows of `python python/benches/bench.py` (`--fitting` runs them alone): each the
whole fit as a caller makes it (the batch's splines ready to evaluate), against SciPy's loop
in the same run on the same data. SciPy's loops that would take minutes or hours run on a
sample of the series and are scaled up (the row says so).

- GCV smoothing: make_smoothing_splines on 8,192 ragged series of 1,900 to 2,200 points (each
  x a jittered grid: sorted uniform draws put points 1e-6 apart, where the criterion itself
  carries rounding), against make_smoothing_spline in a loop over 8 series scaled by 1,024
  (SciPy's GCV costs about a second a series); and one series of 2,048 points;
- make_splpreps on 10,000 noisy 3-D point sequences of 200 points (s given), against
  make_splprep in a loop over 1,000 scaled by 10; make_splreps likewise on 10,000 series;
- make_splpreps with bc_type "periodic" on 2,000 noisy closed 2-D outlines of 200 points,
  against make_splprep's periodic fit in a loop over 100 scaled by 20;
- make_lsq_splines on 10,000 series of 100 points on one knot vector, against
  make_lsq_spline in a loop; and one call of each;
- the legacy doors (FITPACK's own curfit, clocur and regrid: splrep, UnivariateSpline,
  splprep per=1, RectBivariateSpline with s > 0) and a BPoly call, one call each.
"""

from __future__ import annotations

import time

import numpy as np
from timing import Rows, best, faster


def _loop(fit, items, sample: int) -> float:
    """SciPy's loop over the first `sample` items, scaled to all of them (one run)."""
    start = time.perf_counter()
    for item in items[:sample]:
        fit(item)
    return (time.perf_counter() - start) * len(items) / sample


def rows() -> list:
    import warnings

    import scipy.interpolate as scipy

    import splinegpu.interpolate as si


    rng = np.random.default_rng(32)
    out = Rows()

    lengths = rng.integers(1900, 2201, 8192)
    xs = [np.linspace(0, 10, n) + rng.uniform(-0.3, 0.3, n) * 10 / n for n in lengths]
    ys = [np.sin(x) + rng.normal(scale=0.2, size=len(x)) for x in xs]
    a = best(lambda: si.make_smoothing_splines(xs, ys), repeats=1)
    b = _loop(lambda i: scipy.make_smoothing_spline(xs[i], ys[i]), list(range(8192)), 8)
    out.append(("make_smoothing_splines GCV, 8192 x ~2k", a, "SciPy loop, 8 x 1024", b,
                faster(a, b, ">= 10x and < 5 s")))
    x, y = xs[0][:2048], ys[0][:2048]
    a = best(lambda: si.make_smoothing_spline(x, y))
    b = best(lambda: scipy.make_smoothing_spline(x, y), repeats=1)
    out.append(("make_smoothing_spline GCV, 2,048 pts", a, "SciPy (1 run)", b, faster(a, b)))

    u = np.linspace(0, 1, 200)
    curves = [np.stack([np.cos(6 * u), np.sin(6 * u), u]) + rng.normal(scale=0.01,
                                                                        size=(3, 200))
              for _ in range(10_000)]
    s = 200 * 3 * 0.01**2
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        a = best(lambda: si.make_splpreps(curves, s=s), repeats=3)
        b = _loop(lambda c: scipy.make_splprep(c, s=s), curves, 1000)
    out.append(("make_splpreps, 10,000 3-D x 200, s", a, "SciPy loop, 1,000 x 10", b,
                faster(a, b, ">= 10x")))
    angle = np.linspace(0, 2 * np.pi, 200)
    outlines = []
    for _ in range(2_000):
        outline = np.stack([np.cos(angle) * (1 + 0.2 * np.cos(3 * angle)), np.sin(angle)])
        outline += rng.normal(scale=0.01, size=outline.shape)
        outline[:, -1] = outline[:, 0]
        outlines.append(outline)
    s_closed = 200 * 2 * 0.01**2
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        a = best(lambda: si.make_splpreps(outlines, s=s_closed, bc_type="periodic"),
                 repeats=3)
        b = _loop(lambda c: scipy.make_splprep(c, s=s_closed, bc_type="periodic"), outlines,
                  100)
    out.append(("make_splpreps periodic, 2,000 closed 2-D x 200", a, "SciPy loop, 100 x 20",
                b, faster(a, b)))
    series = [np.sort(rng.uniform(0, 10, 200)) for _ in range(10_000)]
    values = [np.sin(x) + rng.normal(scale=0.1, size=200) for x in series]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        a = best(lambda: si.make_splreps(series, values, s=2.0), repeats=3)
        b = _loop(lambda i: scipy.make_splrep(series[i], values[i], s=2.0),
                  list(range(10_000)), 1000)
    out.append(("make_splreps, 10,000 x 200, s", a, "SciPy loop, 1,000 x 10", b,
                faster(a, b)))

    t = np.r_[[0.0] * 4, np.linspace(0, 10, 8)[1:-1], [10.0] * 4]
    series = [np.r_[0.0, np.sort(rng.uniform(0, 10, 98)), 10.0] for _ in range(10_000)]
    values = [np.sin(x) + rng.normal(scale=0.1, size=100) for x in series]
    a = best(lambda: si.make_lsq_splines(series, values, t), repeats=3)
    b = _loop(lambda i: scipy.make_lsq_spline(series[i], values[i], t), list(range(10_000)),
              10_000)
    out.append(("make_lsq_splines, 10,000 x 100", a, "SciPy loop (1 run)", b,
                faster(a, b, ">= 10x")))
    a = best(lambda: si.make_lsq_spline(series[0], values[0], t), calls=100)
    b = best(lambda: scipy.make_lsq_spline(series[0], values[0], t), calls=100)
    out.append(("make_lsq_spline, 100 pts", a, "SciPy", b, faster(a, b)))
    out.extend(_legacy_doors(rng, scipy, si))
    return out


def _legacy_doors(rng, scipy, si) -> list:
    """FITPACK's own fits through the legacy doors (curfit, parcur, clocur, regrid) and a
    BPoly call, one call each as a caller makes it, against SciPy's Fortran on the same data."""
    import warnings

    out = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for n, share, repeats in ((300, 1.0, 5), (1000, 1.0, 5), (10_000, 0.3, 1)):
            x = np.sort(rng.uniform(0, 10, n))
            y = np.sin(x) + rng.normal(scale=0.1, size=n)
            s = share * n * 0.01
            a = best(lambda x=x, y=y, s=s: si.splrep(x, y, s=s), repeats=repeats)
            b = best(lambda x=x, y=y, s=s: scipy.splrep(x, y, s=s), repeats=repeats)
            out.append((f"splrep, {n:,} pts, s = {share} n sigma^2", a, "SciPy", b,
                        faster(a, b)))
        x = np.sort(rng.uniform(0, 10, 1000))
        y = np.sin(x) + rng.normal(scale=0.1, size=1000)
        a = best(lambda: si.UnivariateSpline(x, y, s=10.0))
        b = best(lambda: scipy.UnivariateSpline(x, y, s=10.0))
        out.append(("UnivariateSpline, 1,000 pts", a, "SciPy", b, faster(a, b)))
        u = np.linspace(0, 1, 2000)
        points = [np.cos(6 * u) + rng.normal(scale=0.05, size=2000),
                  np.sin(6 * u) + rng.normal(scale=0.05, size=2000)]
        a = best(lambda: si.splprep(points, s=10.0, per=1))
        b = best(lambda: scipy.splprep(points, s=10.0, per=1))
        out.append(("splprep per=1, 2,000 x 2-D", a, "SciPy", b, faster(a, b)))
        gx, gy = np.sort(rng.uniform(0, 4, 200)), np.sort(rng.uniform(0, 3, 300))
        z = np.sin(gx[:, None]) * np.cos(gy) + rng.normal(scale=0.1, size=(200, 300))
        a = best(lambda: si.RectBivariateSpline(gx, gy, z, s=600.0), repeats=3)
        b = best(lambda: scipy.RectBivariateSpline(gx, gy, z, s=600.0), repeats=3)
        out.append(("RectBivariateSpline s > 0, 200 x 300", a, "SciPy", b, faster(a, b)))
    breaks, c = np.sort(rng.uniform(0, 5, 9)), rng.normal(size=(6, 8))
    xi = np.linspace(0, 5, 1000)
    ours, theirs = si.BPoly(c, breaks), scipy.BPoly(c, breaks)
    a, b = best(lambda: ours(xi), calls=100), best(lambda: theirs(xi), calls=100)
    out.append(("BPoly call, degree 5, 1,000 pts", a, "SciPy", b, faster(a, b)))
    return out
