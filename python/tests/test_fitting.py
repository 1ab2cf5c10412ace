"""Fitting noisy data: make_smoothing_spline(s) and make_lsq_spline(s) against SciPy (the
coefficients within 1e-8 of the largest; GCV's criterion equal to SciPy's and its lam within
1e-6 where the criterion is well conditioned, no worse by SciPy's own criterion where it is
not), against independent derivations (a line is never smoothed; least squares reproduces a
spline of its own space), batches against single fits, and bad input refused with SciPy's
exception types and a message naming the argument."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.interpolate as S
import scipy.interpolate._bsplines as scipy_bsplines

import splinegpu.interpolate as G
from splinegpu import _native


def noisy(rng, n: int, jitter: float = 0.3):
    """n x on [0, 10], each moved up to `jitter` of its step, and a noisy sine on them."""
    x = np.linspace(0, 10, n) + rng.uniform(-jitter, jitter, n) * 10 / n
    return x, np.sin(x) + rng.normal(scale=0.2, size=n)


def close(a, b, tol=1e-8):
    """a within tol of b's largest magnitude (at least 1); NaN where b has NaN."""
    b = np.asarray(b)
    finite = np.abs(b[np.isfinite(b)])
    scale = max(finite.max() if finite.size else 0.0, 1.0)
    np.testing.assert_allclose(a, b, rtol=0, atol=tol * scale)


def scipy_gcv(x, y, w):
    """SciPy's GCV criterion for (x, y, w) and the lam its search chose, captured from a call
    of make_smoothing_spline."""
    seen = {}
    search = scipy_bsplines.minimize_scalar

    def spy(fun, bounds, method, args):
        result = search(fun, bounds=bounds, method=method, args=args)
        seen["criterion"] = lambda lam: fun(lam, *args)
        seen["lam"] = result.x
        return result

    scipy_bsplines.minimize_scalar = spy
    try:
        S.make_smoothing_spline(x, y, w)
    finally:
        scipy_bsplines.minimize_scalar = search
    return seen["criterion"], seen["lam"]


@pytest.mark.parametrize("n", [5, 6, 12, 60, 100])
@pytest.mark.parametrize("weighted", [False, True])
def test_smoothing_spline_matches_scipy(n, weighted):
    rng = np.random.default_rng(n)
    x, y = noisy(rng, n)
    w = rng.uniform(0.5, 2.0, n) if weighted else None
    for lam in (None, 0.0, 1e-3, 1.0, 30.0):
        ours, theirs = G.make_smoothing_spline(x, y, w, lam), S.make_smoothing_spline(x, y, w,
                                                                                     lam)
        np.testing.assert_array_equal(ours.t, theirs.t)
        close(ours.c, theirs.c)
        close(ours(x), theirs(x))
    _, lam = scipy_gcv(x, y, w)
    chosen = G.make_smoothing_spline(x, y, w).lam
    assert abs(chosen - lam) <= 1e-6 * lam


def test_the_gcv_criterion_is_scipys():
    """The criterion itself, at lams over six decades, on data where it is well conditioned."""
    rng = np.random.default_rng(7)
    x, y = noisy(rng, 80)
    w = rng.uniform(0.5, 2.0, 80)
    criterion, _ = scipy_gcv(x, y, w)
    lams = [1e-4, 1e-2, 0.3, 1.0, 10.0, 80.0]
    np.testing.assert_allclose(_native.smoothing_gcv(x, y, w, lams),
                               [criterion(lam) for lam in lams], rtol=1e-9)


@pytest.mark.parametrize("n", [500, 2048])
def test_gcv_is_no_worse_than_scipys_where_the_criterion_is_flat(n):
    """At 500 points and more the criterion carries rounding of 1e-10 or so where it is flat,
    and the two searches part within it: the lam chosen here is then as good by SciPy's own
    criterion (within 1e-9 of its value at SciPy's lam)."""
    rng = np.random.default_rng(n)
    x, y = noisy(rng, n)
    criterion, lam = scipy_gcv(x, y, None)
    chosen = G.make_smoothing_spline(x, y).lam
    assert criterion(chosen) <= criterion(lam) * (1 + 1e-9)


def test_smoothing_columns_have_their_own_lam():
    rng = np.random.default_rng(3)
    x, y = noisy(rng, 40)
    ys = np.stack([y, 3 * y + 1, np.cos(x)], axis=1)
    spline = G.make_smoothing_spline(x, ys)
    assert spline.lam.shape == (3,)
    for j in range(3):
        single = G.make_smoothing_spline(x, ys[:, j])
        assert single.lam == spline.lam[j]
        np.testing.assert_array_equal(single.c, spline.c[:, j])
    # As SciPy's, with y along another axis.
    close(G.make_smoothing_spline(x, ys.T, axis=1).c, S.make_smoothing_spline(x, ys.T, axis=1).c)


def test_a_line_is_never_smoothed():
    """f'' of a line is zero: any lam keeps it, and its B-spline coefficients are its values at
    the Greville abscissae (the averages of three consecutive inner knots)."""
    x = np.array([0.0, 0.3, 1.0, 1.1, 2.5, 4.0, 4.2])
    y = 3 * x - 2
    for lam in (None, 0.0, 1e-2, 1e4):
        spline = G.make_smoothing_spline(x, y, lam=lam)
        greville = (spline.t[1:-3] + spline.t[2:-2] + spline.t[3:-1]) / 3
        close(spline.c, 3 * greville - 2, 1e-10)


def test_smoothing_batch_equals_single_fits():
    rng = np.random.default_rng(11)
    series = [noisy(rng, n) for n in (5, 17, 64, 200)]
    xs, ys = [s[0] for s in series], [s[1] for s in series]
    ws = [rng.uniform(0.5, 2, len(x)) for x in xs]
    batch = G.make_smoothing_splines(xs, ys, ws)
    for i, (x, y, w) in enumerate(zip(xs, ys, ws)):
        single = G.make_smoothing_spline(x, y, w)
        assert batch.lam[i] == single.lam
        np.testing.assert_array_equal(batch[i].c, single.c)
        np.testing.assert_array_equal(batch[i].t, single.t)
    # Evaluation through the batch's pieces.
    values, offsets = batch(xs)
    for i, x in enumerate(xs):
        close(values[offsets[i]:offsets[i + 1], 0], batch[i](x), 1e-12)
    # Given lams: one for all, or one per series.
    fixed = G.make_smoothing_splines(xs, ys, lams=0.5)
    np.testing.assert_array_equal(fixed.lam, 0.5)
    each = G.make_smoothing_splines(xs, ys, lams=[0.1, 0.2, 0.3, 0.4])
    close(each[2].c, S.make_smoothing_spline(xs[2], ys[2], lam=0.3).c)


@pytest.mark.parametrize("k", [0, 1, 2, 3, 5])
def test_lsq_spline_matches_scipy(k):
    rng = np.random.default_rng(k)
    x = np.sort(rng.uniform(0, 1, 60))
    t = np.r_[[0.0] * (k + 1), np.linspace(0, 1, 8)[1:-1], [1.0] * (k + 1)]
    y = np.sin(5 * x) + rng.normal(scale=0.1, size=60)
    w = rng.uniform(0.1, 3.0, 60)
    for weights in (None, w):
        ours, theirs = G.make_lsq_spline(x, y, t, k, weights), S.make_lsq_spline(x, y, t, k,
                                                                                 weights)
        close(ours.c, theirs.c, 1e-12)
    # Many right-hand sides, complex values, and another axis.
    ys = np.stack([y, 2 * y, -y], axis=1) + 1j * np.stack([y, y, y], axis=1)
    close(G.make_lsq_spline(x, ys, t, k).c, S.make_lsq_spline(x, ys, t, k).c, 1e-12)
    close(G.make_lsq_spline(x, ys.T, t, k, axis=-1).c,
          S.make_lsq_spline(x, ys.T, t, k, axis=-1).c, 1e-12)


def test_lsq_reproduces_a_spline_of_its_own_space():
    """Data on a spline of the knots' space is fitted exactly, with repeated x and zero
    weights among them."""
    rng = np.random.default_rng(5)
    t = np.r_[[0.0] * 4, 0.2, 0.45, 0.5, 0.8, [1.0] * 4]
    c = rng.normal(size=len(t) - 4)
    x = np.sort(np.r_[rng.uniform(0, 1, 40), 0.5, 0.5])
    y = S.BSpline(t, c, 3)(x)
    w = np.where(np.arange(42) % 7 == 0, 0.0, 1.0)
    close(G.make_lsq_spline(x, y, t, 3, w).c, c, 1e-12)


def test_lsq_batch_equals_single_fits():
    rng = np.random.default_rng(9)
    t = np.r_[[0.0] * 4, 0.3, 0.6, [1.0] * 4]
    xs = [np.sort(np.r_[0.0, 1.0, rng.uniform(0, 1, n)]) for n in (10, 30, 100)]
    xs[0][1:-1] = np.linspace(0.05, 0.95, 10)
    ys = [np.cos(3 * x) + rng.normal(scale=0.05, size=len(x)) for x in xs]
    batch = G.make_lsq_splines(xs, ys, t)
    for i, (x, y) in enumerate(zip(xs, ys)):
        np.testing.assert_array_equal(batch[i].c, G.make_lsq_spline(x, y, t).c)
    # One knot vector per series, degree 1.
    ts = [np.array([0.0, 0.0, 0.3, 0.7, 1.0, 1.0]), np.array([0.0, 0.0, 0.4, 1.0, 1.0]),
          np.array([0.0, 0.0, 0.5, 0.6, 0.9, 1.0, 1.0])]
    xs = [np.linspace(0, 1, len(x)) for x in xs]
    batch = G.make_lsq_splines(xs, ys, ts, k=1)
    for i in range(3):
        close(batch[i].c, S.make_lsq_spline(xs[i], ys[i], ts[i], 1).c, 1e-12)


def test_batches_read_each_series_as_given():
    """Each series' arrays are its own: weights of the wrong length for their series are
    refused by name even where the lengths add up (short series, copied end to end on their
    way in, and long ones, borrowed one by one), and long series that are views of one array
    (copied end to end) give what separate arrays (borrowed) give, bit for bit."""
    rng = np.random.default_rng(4)
    for n in (12, 1200):
        xs = [np.sort(rng.uniform(0, 1, m)) for m in (n, n - 2)]
        ys = [np.sin(6 * x) + rng.normal(scale=0.1, size=len(x)) for x in xs]
        knots = np.r_[[0.0] * 4, 0.5, [1.0] * 4]
        for fit, args, options in ((G.make_smoothing_splines, (), {}),
                                   (G.make_splreps, (), {"s": 0.1}),
                                   (G.make_lsq_splines, (knots,), {})):
            with pytest.raises(ValueError, match=rf"ws\[0\]: {n - 2} weights for {n} x"):
                fit(xs, ys, *args, ws=[np.ones(n - 2), np.ones(n)], **options)
    flat_x, flat_y = np.concatenate(xs), np.concatenate(ys)
    views = ([flat_x[:n], flat_x[n:]], [flat_y[:n], flat_y[n:]])
    a, b = G.make_smoothing_splines(*views), G.make_smoothing_splines(xs, ys)
    np.testing.assert_array_equal(a.lam, b.lam)
    for i in range(2):
        np.testing.assert_array_equal(a[i].c, b[i].c)


def test_bad_input_is_refused_by_name():
    x = np.linspace(0, 1, 10)
    y = x**2
    with pytest.raises(ValueError, match="ascending"):
        G.make_smoothing_spline(x[::-1], y)
    with pytest.raises(ValueError, match="Invalid vector of weights"):
        G.make_smoothing_spline(x, y, w=-np.ones(10))
    with pytest.raises(ValueError, match="w: one weight per x"):
        G.make_smoothing_spline(x, y, w=np.ones(9))
    with pytest.raises(ValueError, match="at least 5"):
        G.make_smoothing_spline(x[:4], y[:4])
    with pytest.raises(ValueError, match="non-negative"):
        G.make_smoothing_spline(x, y, lam=-1.0)
    with pytest.raises(ValueError, match="complex"):
        G.make_smoothing_spline(x, y + 1j)
    with pytest.raises(ValueError, match="finite"):
        G.make_smoothing_spline(x, np.r_[y[:-1], np.nan])
    with pytest.raises(ValueError, match=r"xs\[1\]: ``x`` should be an ascending array"):
        G.make_smoothing_splines([x, x[::-1]], [y, y])
    with pytest.raises(ValueError, match=r"ws\[0\]: Invalid vector of weights"):
        G.make_smoothing_splines([x], [y], ws=[np.zeros(10)])
    t = np.r_[[0.0] * 4, 0.5, [1.0] * 4]
    with pytest.raises(ValueError, match="Need more x points"):
        G.make_lsq_spline(x[:3], y[:3], t)
    with pytest.raises(ValueError, match="non-decreasing"):
        G.make_lsq_spline(x[::-1], y, t)
    with pytest.raises(ValueError, match="Out of bounds"):
        G.make_lsq_spline(x * 2, y, t)
    with pytest.raises(ValueError, match="w: weights must be finite and >= 0"):
        G.make_lsq_spline(x, y, t, w=-np.ones(10))
    with pytest.raises(ValueError, match="Shapes of x"):
        G.make_lsq_spline(x, y, t, w=np.ones(9))
    with pytest.raises(ValueError, match="Schoenberg-Whitney"):
        G.make_lsq_spline(np.linspace(0, 0.3, 10), y, np.r_[[0.0] * 4, 0.5, 0.6, 0.7,
                                                             [1.0] * 4])
    with pytest.raises(ValueError, match=r"series 1: .*Schoenberg-Whitney"):
        G.make_lsq_splines([x, np.r_[np.linspace(0, 0.3, 9), 1.0]], [y, y],
                           np.r_[[0.0] * 4, 0.5, 0.6, 0.7, [1.0] * 4])
    with pytest.raises(ValueError, match=r"xs\[0\]: Out of bounds"):
        G.make_lsq_splines([x * 2], [y], t)
    with pytest.raises(ValueError, match="Unknown method"):
        G.make_lsq_spline(x, y, t, method="svd")


def smoothing_data(rng, m: int = 60, d: int = 1):
    x = np.sort(rng.uniform(0, 10, m))
    y = np.stack([np.sin(x + j) for j in range(d)], axis=1) + rng.normal(scale=0.3,
                                                                        size=(m, d))
    return x, (y[:, 0] if d == 1 else y)


@pytest.mark.parametrize("k", [1, 2, 3, 4, 5])
def test_make_splrep_matches_scipy(k):
    """FITPACK's knots bit for bit and the coefficients within 1e-8 of the largest (1e-12 or
    so for k <= 3; 7e-9 at worst for k = 5, where dozens of knots make the rotations'
    rounding show), over smoothings from near-interpolation to a polynomial, with weights
    and a wider interval."""
    rng = np.random.default_rng(k)
    x, y = smoothing_data(rng)
    w = rng.uniform(0.5, 2.0, len(x))
    for s in (0.2, 2.0, 10.0, 1e3):
        for kw in ({}, {"w": w}, {"xb": -1.0, "xe": 11.0}):
            ours = G.make_splrep(x, y, k=k, s=s, **kw)
            theirs = S.make_splrep(x, y, k=k, s=s, **kw)
            np.testing.assert_array_equal(ours.t, theirs.t)
            close(ours.c, theirs.c)
    # Given knots: the smoothing step alone.
    t = S.make_splrep(x, y, k=k, s=2.0).t
    close(G.make_splrep(x, y, k=k, s=5.0, t=t).c, S.make_splrep(x, y, k=k, s=5.0, t=t).c)


def test_make_splprep_matches_scipy_and_batches_equal_singles():
    rng = np.random.default_rng(4)
    u = np.linspace(0, 1, 80)
    curves = [np.stack([np.cos(6 * u), np.sin(6 * u), u]) + rng.normal(scale=0.02,
                                                                        size=(3, 80))
              for _ in range(4)]
    s = 80 * 0.02**2 * 3
    batch, us = G.make_splpreps(curves, s=s)
    for i, points in enumerate(curves):
        ours, u_ours = G.make_splprep(points, s=s)
        theirs, u_theirs = S.make_splprep(points, s=s)
        np.testing.assert_array_equal(u_ours, u_theirs)
        np.testing.assert_array_equal(ours.t, theirs.t)
        close(ours.c, theirs.c, 1e-10)
        np.testing.assert_array_equal(batch[i].t, ours.t)
        np.testing.assert_array_equal(batch[i].c, ours.c)
        np.testing.assert_array_equal(us[i], u_ours)
        close(batch[i](u_ours), ours(u_ours).T, 1e-12)
    xs = [np.sort(rng.uniform(0, 10, n)) for n in (20, 50, 90)]
    ys = [np.sin(x) + rng.normal(scale=0.2, size=len(x)) for x in xs]
    batch = G.make_splreps(xs, ys, s=[1.0, 2.0, 3.0], k=2)
    for i, (x, y) in enumerate(zip(xs, ys)):
        single = G.make_splrep(x, y, s=[1.0, 2.0, 3.0][i], k=2)
        np.testing.assert_array_equal(batch[i].t, single.t)
        np.testing.assert_array_equal(batch[i].c, single.c)


def periodic_data(rng, n: int):
    """n points on [0, 2 pi] (ends included, the rest uniform draws) and a noisy periodic
    function on them, its last value its first."""
    x = np.r_[0.0, np.sort(rng.uniform(0, 2 * np.pi, n - 2)), 2 * np.pi]
    y = np.sin(x) + np.cos(2 * x) + rng.normal(scale=0.1, size=n)
    y[-1] = y[0]
    return x, y


@pytest.mark.parametrize("k", [1, 2, 3, 4, 5])
def test_periodic_make_splrep_matches_scipy(k):
    """FITPACK's periodic knots bit for bit and the coefficients within 1e-10 of the largest,
    from near-interpolation (hundreds of knots: the rotations meet leftovers of 1e-163
    against untouched rows) to the constant, with weights and given knots."""
    rng = np.random.default_rng(30 + k)
    for n, s in ((11, 1e-2), (51, 0.3), (100, 1.0), (300, 1e-2), (40, 1e3)):
        x, y = periodic_data(rng, n)
        w = rng.uniform(0.5, 2.0, n)
        for kw in ({}, {"w": w}):
            ours = G.make_splrep(x, y, k=k, s=s, bc_type="periodic", **kw)
            theirs = S.make_splrep(x, y, k=k, s=s, bc_type="periodic", **kw)
            np.testing.assert_array_equal(ours.t, theirs.t)
            close(ours.c, theirs.c, 1e-10)
    t = S.make_splrep(x, y, k=k, s=20.0, bc_type="periodic").t
    close(G.make_splrep(x, y, k=k, s=30.0, t=t, bc_type="periodic").c,
          S.make_splrep(x, y, k=k, s=30.0, t=t, bc_type="periodic").c, 1e-10)


def test_periodic_fits_are_periodic_and_meet_s():
    """Independently of SciPy: the fitted spline and its first k - 1 derivatives agree at the
    period's two ends, and fp over the first m - 1 points is s within FITPACK's tolerance
    (s / 1000)."""
    rng = np.random.default_rng(41)
    x, y = periodic_data(rng, 60)
    for k in (2, 3, 5):
        s = 0.4
        spline = G.make_splrep(x, y, k=k, s=s, bc_type="periodic")
        for nu in range(k):
            ends = spline([x[0], x[-1]], nu=nu)
            close(ends[0], ends[1], 1e-9)
        fp = np.sum((y[:-1] - spline(x[:-1])) ** 2)
        assert abs(fp - s) < s * 1e-3


def test_periodic_curves_and_legacy_doors_match_scipy():
    """Closed curves (make_splprep and a batch of them) and the tck doors with per=1: SciPy's
    knots, and coefficients within 1e-10; splrep(per=1) on data that is not periodic (percur
    leaves the last value out): SciPy's Fortran percur's interpolation and smoothing, meeting
    s. splprep(per=1) is FITPACK's clocur, whose knots SciPy's make_splprep places elsewhere."""
    rng = np.random.default_rng(44)
    u = np.linspace(0, 2 * np.pi, 70)
    curves = []
    for _ in range(3):
        points = np.stack([np.cos(u), np.sin(2 * u)]) + rng.normal(scale=0.02, size=(2, 70))
        points[:, -1] = points[:, 0]
        curves.append(points)
    batch, us = G.make_splpreps(curves, s=0.05, bc_type="periodic")
    for i, points in enumerate(curves):
        ours, u_ours = G.make_splprep(points, s=0.05, bc_type="periodic")
        theirs, _ = S.make_splprep(points, s=0.05, bc_type="periodic")
        np.testing.assert_array_equal(ours.t, theirs.t)
        close(ours.c, theirs.c, 1e-10)
        np.testing.assert_array_equal(batch[i].t, ours.t)
        np.testing.assert_array_equal(batch[i].c, ours.c)
        np.testing.assert_array_equal(us[i], u_ours)
        # splprep(per=1) is FITPACK's clocur (SciPy's splprep).
        tck, u_legacy = G.splprep(points, s=0.05, per=1)
        tck2, u2 = S.splprep(points, s=0.05, per=1)
        np.testing.assert_array_equal(u_legacy, u_ours)
        np.testing.assert_array_equal(u_legacy, u2)
        np.testing.assert_array_equal(tck[0], tck2[0])
        close(np.asarray(G.splev(u2, tck)), np.asarray(S.splev(u2, tck2)), 1e-10)
    x = np.linspace(0, 2 * np.pi, 25)
    y = np.exp(x / 3)
    for k in (1, 2, 3, 5):
        ours, theirs = G.splrep(x, y, k=k, s=0, per=1), S.splrep(x, y, k=k, s=0, per=1)
        close(ours[0], theirs[0], 1e-15)  # the knots past the ends: an ulp apart
        close(ours[1], theirs[1], 1e-9)
        for s in (0.5, 3.0):
            (t, c, _), fp, _, _ = G.splrep(x, y, k=k, s=s, per=1, full_output=1)
            (t2, c2, _), fp2, _, _ = S.splrep(x, y, k=k, s=s, per=1, full_output=1)
            np.testing.assert_array_equal(t, t2)
            close(c, c2, 1e-10)
            assert abs(fp - s) < s * 1e-3 and abs(fp - fp2) <= 1e-10 * fp2


def test_fitpack_bad_input_is_refused_by_name():
    x = np.linspace(0, 1, 20)
    y = np.sin(x)
    with pytest.raises(ValueError, match="`s` must be non-negative"):
        G.make_splrep(x, y, s=-1.0)
    with pytest.raises(ValueError, match="Weights must be non-negative"):
        G.make_splrep(x, y, s=1.0, w=-np.ones(20))
    with pytest.raises(ValueError, match="All weights are zero"):
        G.make_splrep(x, y, s=1.0, w=np.zeros(20))
    with pytest.raises(ValueError, match="ordered 1D sequence"):
        G.make_splrep(x[::-1], y, s=1.0)
    with pytest.raises(ValueError, match="Schoenberg-Whitney"):
        G.make_splrep(x, y, s=1.0, t=np.r_[[0.0] * 4, 0.01, 0.02, 0.03, [1.0] * 4])
    with pytest.raises(ValueError, match="First and last points does not match"):
        G.make_splrep(x, y, s=1.0, bc_type="periodic")
    with pytest.raises(ValueError, match=r"ys\[1\]: First and last points does not match"):
        G.make_splreps([x, x], [np.r_[y[:-1], y[0]], y], s=1.0, bc_type="periodic")
    with pytest.raises(ValueError, match="Schoenberg-Whitney"):
        # Five inner knots between two points: one B-spline's support holds no point.
        G.make_splrep(x, np.r_[y[:-1], y[0]], s=1.0, bc_type="periodic",
                      t=np.r_[-0.014, -0.013, -0.012, 0.0, 0.01, 0.011, 0.012, 0.013, 0.014,
                              1.0, 1.01, 1.011, 1.012])
    with pytest.raises(ValueError, match="bc_type"):
        G.make_splrep(x, y, s=1.0, bc_type="natural")
    with pytest.raises(ValueError, match=r"xs\[1\]: Expect `x` to be an ordered"):
        G.make_splreps([x, x[::-1]], [y, y], s=1.0)
    with pytest.raises(ValueError, match=r"ws\[0\]: Weights must be non-negative"):
        G.make_splreps([x], [y], ws=[-np.ones(20)], s=1.0)
    with pytest.raises(ValueError, match="s: every series' s must be > 0"):
        G.make_splreps([x], [y], s=0.0)


@pytest.mark.parametrize("kind", ["linear", "nearest", "nearest-up", "zero", "slinear",
                                  "quadratic", "cubic", "previous", "next", 5])
def test_interp1d_matches_scipy(kind):
    rng = np.random.default_rng(2)
    x = rng.permutation(np.sort(rng.uniform(0, 10, 15)))
    y = rng.normal(size=(3, 15))
    xi = np.linspace(-1, 11, 50).reshape(5, 10)
    for kw in ({"fill_value": "extrapolate"}, {"bounds_error": False, "fill_value": (-1, 2)},
               {"bounds_error": False}):
        ours = G.interp1d(x, y, kind=kind, **kw)(xi)
        theirs = S.interp1d(x, y, kind=kind, **kw)(xi)
        assert ours.shape == theirs.shape
        close(ours, theirs, 1e-10)
    ours = G.interp1d(x, y.T, kind=kind, axis=0, bounds_error=False)(xi)
    close(ours, S.interp1d(x, y.T, kind=kind, axis=0, bounds_error=False)(xi), 1e-10)
    with pytest.raises(ValueError, match="below the interpolation range"):
        G.interp1d(x, y, kind=kind)(np.array([-5.0]))


def test_legacy_doors_match_scipy():
    rng = np.random.default_rng(8)
    x = np.sort(rng.uniform(0, 10, 40))
    y = np.sin(x)
    for k in (1, 3, 5):
        ours, theirs = G.splrep(x, y, k=k), S.splrep(x, y, k=k)
        np.testing.assert_array_equal(ours[0], theirs[0])
        close(ours[1], theirs[1], 1e-10)
        xi = np.linspace(-1, 11, 33)
        for ext in (0, 1, 3):
            close(G.splev(xi, ours, ext=ext), S.splev(xi, theirs, ext=ext), 1e-9)
        close(G.splint(1.0, 7.5, ours), S.splint(1.0, 7.5, theirs), 1e-10)
        d, dd = G.splder(ours), S.splder(theirs)
        np.testing.assert_array_equal(d[0], dd[0])
        close(d[1], dd[1], 1e-9)
        a, aa = G.splantider(ours), S.splantider(theirs)
        close(a[1], aa[1], 1e-9)
    close(G.sproot(G.splrep(x, y)), S.sproot(S.splrep(x, y)), 1e-9)
    # Least squares on given interior knots, and a parametric curve.
    t = [2.0, 4.0, 6.0, 8.0]
    close(G.splrep(x, y, t=t)[1], S.splrep(x, y, t=t)[1], 1e-10)
    (tck, u), (tck2, u2) = G.splprep([np.cos(x), np.sin(x)]), S.splprep([np.cos(x), np.sin(x)])
    np.testing.assert_array_equal(tck[0], tck2[0])
    close(np.asarray(tck[1]), np.asarray(tck2[1]), 1e-10)
    close(np.asarray(G.splev(u, tck)), np.asarray(S.splev(u2, tck2)), 1e-10)
    # Least squares on given knots (task=-1: t's inner knots, the ends [ub, ue]).
    knots = np.r_[[0.0] * 4, 0.3, 0.6, [1.0] * 4]
    (tck, u), (tck2, u2) = (G.splprep([np.cos(x), np.sin(x)], task=-1, t=knots),
                            S.splprep([np.cos(x), np.sin(x)], task=-1, t=knots))
    np.testing.assert_array_equal(tck[0], tck2[0])
    close(np.asarray(tck[1]), np.asarray(tck2[1]), 1e-10)


def test_univariate_splines_match_scipy():
    rng = np.random.default_rng(12)
    x = np.sort(rng.uniform(0, 10, 50))
    y = np.sin(x) + rng.normal(scale=0.1, size=50)
    xi = np.linspace(-1, 11, 40)
    for k in (1, 3, 5):
        ours, theirs = G.InterpolatedUnivariateSpline(x, y, k=k), \
            S.InterpolatedUnivariateSpline(x, y, k=k)
        close(ours(xi), theirs(xi), 1e-9)
        close(ours.get_coeffs(), theirs.get_coeffs(), 1e-9)
        ours = G.LSQUnivariateSpline(x, y, [2.0, 5.0, 7.5], k=k, ext="const")
        theirs = S.LSQUnivariateSpline(x, y, [2.0, 5.0, 7.5], k=k, ext="const")
        close(ours(xi), theirs(xi), 1e-10)
        close(ours.get_residual(), theirs.get_residual(), 1e-10)
        close(ours.integral(-2, 5), theirs.integral(-2, 5), 1e-10)
    # Smoothing: FITPACK's curfit's knots and fit (s = len(x) by default).
    ours = G.UnivariateSpline(x, y, w=np.full(50, 10.0))
    theirs = S.UnivariateSpline(x, y, w=np.full(50, 10.0))
    np.testing.assert_array_equal(ours.get_knots(), theirs.get_knots())
    close(ours.get_coeffs(), theirs.get_coeffs(), 1e-10)
    close(ours.derivatives(4.0), theirs.derivatives(4.0), 1e-10)


def test_set_smoothing_factor_goes_on_from_the_knots_found():
    """FITPACK's curfit with iopt = 1: a larger s keeps the knots and smooths on them (SciPy's
    answer, its knots exactly, its coefficients within 1e-10); a smaller s only adds knots,
    to fp = s within FITPACK's tolerance; an s the polynomial meets gives the polynomial;
    given knots stay, with SciPy's warning."""
    rng = np.random.default_rng(7)
    for _ in range(12):
        n = int(rng.integers(20, 200))
        x = np.sort(rng.uniform(0, 10, n))
        y = np.sin(x) + rng.normal(scale=0.2, size=n)
        s1 = rng.uniform(1.0, 2.0) * n * 0.04
        ours, theirs = G.UnivariateSpline(x, y, s=s1), S.UnivariateSpline(x, y, s=s1)
        knots = ours.get_knots()
        np.testing.assert_array_equal(knots, theirs.get_knots())
        ours.set_smoothing_factor(2 * s1)
        theirs.set_smoothing_factor(2 * s1)
        np.testing.assert_array_equal(ours.get_knots(), knots)
        close(ours.get_coeffs(), theirs.get_coeffs(), 1e-10)
        ours.set_smoothing_factor(s1 / 4)
        assert set(knots) <= set(ours.get_knots())
        assert abs(ours.get_residual() - s1 / 4) <= s1 / 4 * 1e-3
        ours.set_smoothing_factor(1e6)
        assert len(ours.get_knots()) == 2
    x = np.linspace(0, 1, 30)
    lsq = G.LSQUnivariateSpline(x, np.sin(x), [0.5])
    with pytest.warns(UserWarning, match="smoothing factor unchanged"):
        lsq.set_smoothing_factor(1.0)


def test_far_apart_weights_keep_scipys_knots(far_apart_weights):
    """Weights 1e12 against 1e2 to 1e3 (SciPy's gh-1375 data): they square to 1e24 in the
    normal equations, so the knot search rotates; the heavy points' residuals are then the
    basis recurrence's rounding, which FITPACK's divisions fix, and fp is summed at the data."""
    x, y, w = far_apart_weights
    for s in (5.0, 13.0):
        ours, theirs = G.make_splrep(x, y, w=w, s=s), S.make_splrep(x, y, w=w, s=s)
        np.testing.assert_array_equal(ours.t, theirs.t)
        close(ours(x), theirs(x), 1e-8)


def test_fitted_curves_tessellate_as_nurbs():
    """A make_splpreps batch's curves go to the curve machinery as they are: their knots and
    control points are a "nurbs" curve's (unit weights), sampled per segment, at given t and
    by arc length on the CPU context."""
    import splinegpu

    rng = np.random.default_rng(6)
    u = np.linspace(0, 1, 60)
    curves = [np.stack([np.cos(5 * u), np.sin(5 * u), u]) + rng.normal(scale=0.01,
                                                                        size=(3, 60))
              for _ in range(3)]
    batch, _ = G.make_splpreps(curves, s=60 * 3e-4)
    ctx = splinegpu.Context("cpu")
    knots = [batch[i].t for i in range(3)]
    points = [np.asarray(batch[i].c) for i in range(3)]
    for sampling in ({"per_segment": 5}, {"arc_length": 40}):
        made = ctx.tessellate(points, kind="nurbs", knots=knots, **sampling)
        for i in range(3):
            rows = slice(made.curve_offsets[i], made.curve_offsets[i + 1])
            close(made.points[rows], batch[i](made.t[rows]), 1e-12)


def test_bad_batch_arguments_are_named():
    # Each raised IndexError or a NumPy reshape/broadcast error before.
    x = np.linspace(0, 1, 20)
    with pytest.raises(ValueError, match=r"x: needs more points than the degree k = 3, got 1"):
        G.make_splprep([np.array([1.0]), np.array([2.0])])
    with pytest.raises(ValueError, match=r"ys\[1\]: a series of no values"):
        G.make_smoothing_splines([x, np.zeros(0)], [x, np.zeros(0)])
    with pytest.raises(ValueError, match=r"ys\[1\]: a series of no values"):
        G.CubicSplines([x, np.zeros(0)], [x, np.zeros(0)])
    with pytest.raises(ValueError, match=r"points\[1\]: needs more points than the degree"):
        G.make_splpreps([np.stack([x, x]), np.zeros((2, 0))], s=0.1)
    with pytest.raises(ValueError, match=r"k: a batch's splines are evaluated up to degree 3"):
        G.make_splreps([x, x], [np.sin(x), np.cos(x)], k=6, s=0.1)
    with pytest.raises(ValueError, match=r"s: one value, or one per series \(2\), got shape"):
        G.make_splreps([x, x], [np.sin(x), np.cos(x)], s=[0.1, 0.2, 0.3])


def test_splprep_of_complex_points_raises_as_scipy_does():
    # The imaginary part was dropped with a ComplexWarning before; SciPy's splprep raises
    # TypeError (its splrep warns and drops it, as ours does).
    x = np.linspace(0, 1, 10)
    with pytest.raises(TypeError):
        S.splprep([x, x + 1j * x])
    with pytest.raises(TypeError, match="complex128"):
        G.splprep([x, x + 1j * x])
