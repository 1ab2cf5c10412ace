"""Gridded data: NdBSpline, RegularGridInterpolator / interpn and RectBivariateSpline against
SciPy (1e-10 of the largest value inside the grid, on uneven axes with spacing ratios to 1e3
and values near 1e6), against independent derivations (a tensor cubic is reproduced by the
not-a-knot cubic; the nodes are interpolated), and bad input refused with SciPy's exception
types and a message naming the argument."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.interpolate as S
import scipy.sparse.linalg as ssl
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import splinegpu.interpolate as G

METHODS = ["linear", "nearest", "slinear", "cubic", "quintic", "pchip"]


def uneven_axis(rng, n: int, ratio: float) -> np.ndarray:
    """n strictly increasing points whose steps span `ratio` (smallest to largest)."""
    steps = np.exp(rng.uniform(0, np.log(ratio), n - 1))
    steps[rng.integers(n - 1)] = 1.0
    steps[rng.integers(n - 1)] = ratio
    return np.concatenate([[0.0], np.cumsum(steps)]) + rng.uniform(-5, 5)


def inside(rng, grid, count: int) -> np.ndarray:
    return np.stack([rng.uniform(g[0], g[-1], count) for g in grid], axis=-1)


def scipy_rgi(grid, values, method, **kw):
    if method in ("slinear", "cubic", "quintic"):
        kw["solver"] = ssl.spsolve  # SciPy's exact construction (its default iterates to 1e-6)
    return S.RegularGridInterpolator(grid, values, method=method, **kw)


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), dims=st.integers(1, 3),
       method=st.sampled_from(METHODS), ratio=st.sampled_from([1.0, 10.0, 1e3]),
       mean=st.sampled_from([0.0, 1e6]))
def test_rgi_matches_scipy_on_uneven_axes(seed, dims, method, ratio, mean):
    # A quintic grid of 2-3 axes at a 1e3 spacing ratio overshoots its data by up to 1e10:
    # no two solvers agree there to better than 1e-8 of that.
    assume(not (method == "quintic" and ratio > 10 and dims > 1))
    rng = np.random.default_rng(seed)
    grid = tuple(uneven_axis(rng, int(rng.integers(6, 12)), ratio) for _ in range(dims))
    values = mean + rng.normal(size=tuple(len(g) for g in grid))
    xi = inside(rng, grid, 300)
    want = scipy_rgi(grid, values, method)(xi)
    got = G.RegularGridInterpolator(grid, values, method=method)(xi)
    assert got.shape == want.shape
    # The largest value: of the data or, where a high degree on uneven steps overshoots them
    # (quintic at a 1e3 spacing ratio reaches 100x the data), of the interpolant.
    largest = max(np.abs(values).max(), np.abs(want).max())
    # At a 1e3 spacing ratio the collocation is ill-conditioned (1-D cubic: measured errors
    # against the exact rational solution to 1.6e-11 of the largest value for SciPy's banded
    # make_interp_spline, 7e-12 for this fit; quintic to 1e-9 for each), and a grid's
    # condition is the product of its axes': SciPy's spsolve, its make_interp_spline and this
    # fit agree to that, not to 1e-10.
    if ratio > 10 and method in ("cubic", "quintic"):
        bound = 1e-8 if method == "quintic" else 1e-9
    else:
        bound = 1e-10
    np.testing.assert_allclose(got, want, rtol=0, atol=bound * largest)


@pytest.mark.parametrize("method", METHODS)
def test_rgi_trailing_values_fill_nan_and_descending(method):
    rng = np.random.default_rng(1)
    grid = (np.linspace(0, 1, 7), np.sort(rng.uniform(-2, 2, 8))[::-1])
    values = rng.normal(size=(7, 8, 2, 3))
    xi = np.concatenate([inside(rng, (grid[0], grid[1][::-1]), 50),
                         [[np.nan, 0.0], [-1.0, 0.0], [0.5, 9.0]]])
    for fill in (np.nan, 2.5, None):
        want = scipy_rgi(grid, values, method, bounds_error=False, fill_value=fill)(xi)
        got = G.RegularGridInterpolator(grid, values, method=method, bounds_error=False,
                                        fill_value=fill)(xi)
        assert got.shape == want.shape == (53, 2, 3)
        np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-9, equal_nan=True)


def test_cubic_reproduces_a_tensor_cubic_and_its_derivatives():
    # The not-a-knot cubic holds every cubic: p(x, y, z) exactly, with its derivatives.
    rng = np.random.default_rng(2)
    grid = tuple(uneven_axis(rng, 9, 100.0) / 50 for _ in range(3))

    def p(x, y, z):
        return 1e6 + x**3 - 2 * x * y**2 + 3 * y * z**3 + z

    values = p(*np.meshgrid(*grid, indexing="ij"))
    rgi = G.RegularGridInterpolator(grid, values, method="cubic")
    xi = inside(rng, grid, 400)
    x, y, z = xi.T
    np.testing.assert_allclose(rgi(xi), p(x, y, z), rtol=0, atol=1e-9 * 1e6)
    np.testing.assert_allclose(rgi(xi, nu=(0, 1, 1)), 9 * z**2, rtol=1e-7, atol=1e-6)


def test_large_mean_interpolates_the_nodes():
    # scipy#23356: values 1e6 plus small variations; the separable solve is exact, so the
    # interpolant passes through every node to rounding.
    rng = np.random.default_rng(3)
    grid = (np.arange(40.0), np.arange(30.0))
    values = 1e6 + rng.normal(scale=1e-3, size=(40, 30))
    nodes = np.stack(np.meshgrid(*grid, indexing="ij"), axis=-1).reshape(-1, 2)
    got = G.RegularGridInterpolator(grid, values, method="cubic")(nodes)
    np.testing.assert_allclose(got, values.ravel(), rtol=0, atol=1e-9)


@pytest.mark.parametrize("k", [(3, 3), (1, 2), (5, 0), (2, 4, 3)])
def test_ndbspline_matches_scipy(k):
    rng = np.random.default_rng(4)
    t = tuple(np.concatenate([[0.0] * (kd + 1), np.sort(rng.uniform(0, 5, 4)), [5.0] * (kd + 1)])
              for kd in k)
    c = rng.normal(size=(*tuple(len(td) - kd - 1 for td, kd in zip(t, k)), 2))
    xi = rng.uniform(-1, 6, (500, len(k)))
    ours, theirs = G.NdBSpline(t, c, k), S.NdBSpline(t, c, k)
    for nu in (None, (1,) * len(k), tuple(kd + 1 for kd in k)):
        np.testing.assert_allclose(ours(xi, nu=nu), theirs(xi, nu=nu), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(ours(xi, extrapolate=False), theirs(xi, extrapolate=False),
                               rtol=1e-12, atol=1e-12, equal_nan=True)
    derived = ours.derivative((1,) * len(k))
    np.testing.assert_allclose(derived.c, theirs.derivative((1,) * len(k)).c, atol=1e-12)
    xc = np.ascontiguousarray(xi)
    np.testing.assert_allclose(ours.design_matrix(xc, t, k).toarray(),
                               theirs.design_matrix(xc, t, k).toarray(), atol=1e-15)


def test_ndbspline_complex_and_pickle():
    import pickle

    rng = np.random.default_rng(5)
    t = (np.r_[0, 0, 0, 0, 1, 2, 2, 2, 2.0], np.r_[0, 0, 1, 2, 3, 3.0])
    c = rng.normal(size=(5, 4)) + 1j * rng.normal(size=(5, 4))
    xi = rng.uniform(0, 2, (20, 2))
    spline = G.NdBSpline(t, c, (3, 1))
    want = S.NdBSpline(t, c, (3, 1))(xi)
    np.testing.assert_allclose(spline(xi), want, atol=1e-13)
    np.testing.assert_allclose(pickle.loads(pickle.dumps(spline))(xi), want, atol=1e-13)


@pytest.mark.parametrize("kx, ky", [(3, 3), (1, 2), (5, 4), (2, 5)])
def test_rect_bivariate_spline_matches_fitpack(kx, ky):
    rng = np.random.default_rng(6)
    x, y = uneven_axis(rng, 12, 1e3), uneven_axis(rng, 9, 30.0)
    z = 1e6 + rng.normal(size=(12, 9))
    ours, theirs = G.RectBivariateSpline(x, y, z, kx=kx, ky=ky), \
        S.RectBivariateSpline(x, y, z, kx=kx, ky=ky)
    for a, b in zip(ours.get_knots(), theirs.get_knots()):
        np.testing.assert_array_equal(a, b)
    scale = 1e-10 * 1e6
    xs = np.sort(rng.uniform(x[0] - 1, x[-1] + 1, 30))
    ys = np.sort(rng.uniform(y[0] - 1, y[-1] + 1, 20))
    np.testing.assert_allclose(ours(xs, ys), theirs(xs, ys), atol=scale)
    np.testing.assert_allclose(ours.ev(xs, ys[:1]), theirs.ev(xs, ys[:1]), atol=scale)
    dx = 1 if kx > 1 else 0  # FITPACK (and this class) refuse dx >= kx
    np.testing.assert_allclose(ours(xs, ys, dx=dx), theirs(xs, ys, dx=dx), rtol=1e-8,
                               atol=scale)
    with pytest.raises(ValueError):
        ours(xs, ys, dx=kx)
    np.testing.assert_allclose(ours.integral(x[1], x[-1] + 5, y[0] - 1, y[4]),
                               theirs.integral(x[1], x[-1] + 5, y[0] - 1, y[4]), rtol=1e-10)


def test_bad_input_is_named():
    grid = (np.arange(5.0), np.arange(4.0))
    values = np.zeros((5, 4))
    with pytest.raises(ValueError, match="dimension 1 must be strictly ascending"):
        G.RegularGridInterpolator((grid[0], [0, 2, 1, 3]), values)
    with pytest.raises(ValueError, match="4 points and 3 values in dimension 1"):
        G.RegularGridInterpolator(grid, np.zeros((5, 3)))
    rgi = G.RegularGridInterpolator(grid, values)
    with pytest.raises(ValueError, match="out of bounds in dimension 0"):
        rgi([[np.nan, 1.0]])
    with pytest.raises(ValueError, match="dimension 3 but this RegularGridInterpolator has "
                                         "dimension 2"):
        rgi([[1.0, 1.0, 1.0]])
    with pytest.raises(ValueError, match="Method 'quartic' is not defined"):
        G.RegularGridInterpolator(grid, values, method="quartic")
    with pytest.raises(ValueError, match="requires at least  6 points"):
        G.RegularGridInterpolator(grid, values, method="quintic")
    with pytest.raises(ValueError, match="maxit: must be a positive integer"):
        G.RectBivariateSpline(grid[0], grid[1], values, s=1.0, maxit=0)
    with pytest.raises(ValueError, match="dimension 0 are inconsistent"):
        G.NdBSpline((np.r_[0, 0, 1, 1.0], np.r_[0, 0, 1, 1.0]), np.zeros((3, 2)), 1)


@pytest.mark.parametrize("method", METHODS)
def test_a_nan_does_not_hide_a_point_outside(method):
    # The bounds are read per axis with min and max, which NaN poisons: a point outside in an
    # axis that also holds a NaN must still get fill_value.
    grid = (np.linspace(0, 1, 7), np.linspace(0, 2, 8))
    values = np.arange(56.0).reshape(7, 8)
    xi = np.array([[np.nan, 1.0], [-5.0, 1.0], [0.5, 1.0], [0.5, np.nan]])
    if method == "pchip":
        # SciPy refuses a NaN past the first coordinate here; so does this class, by name.
        with pytest.raises(ValueError, match="xi: a NaN coordinate in dimension 1"):
            G.RegularGridInterpolator(grid, values, method=method, bounds_error=False)(xi)
        xi = xi[:3]
    got = G.RegularGridInterpolator(grid, values, method=method, bounds_error=False,
                                    fill_value=7.0)(xi)
    want = scipy_rgi(grid, values, method, bounds_error=False, fill_value=7.0)(xi)
    np.testing.assert_allclose(got, want, equal_nan=True, atol=1e-12)
    assert np.isnan(got[0]) and got[1] == 7.0


@pytest.mark.parametrize("method", METHODS)
def test_ragged_grid_batch_equals_each_interpolator(method):
    rng = np.random.default_rng(7)
    grids, values, xis = [], [], []
    for i in range(12):
        d = 2 if i % 3 else 3
        grid = tuple(uneven_axis(rng, int(rng.integers(6, 11)), 10.0) for _ in range(d))
        grids.append(grid)
        values.append(rng.normal(size=(*(len(g) for g in grid), 2)))
        xi = inside(rng, grid, int(rng.integers(0, 40)))
        if len(xi):
            xi[0, 0] = grid[0][0] - 1.0  # one point outside: the fill value
        xis.append(xi)
    batch = G.RegularGridInterpolators(grids, values, method=method, bounds_error=False,
                                       fill_value=-9.0)
    got, offsets = batch(xis)
    assert got.shape == (sum(len(x) for x in xis), 2)
    for i, (grid, v, xi) in enumerate(zip(grids, values, xis)):
        want = scipy_rgi(grid, v, method, bounds_error=False, fill_value=-9.0)(xi)
        np.testing.assert_allclose(got[offsets[i]:offsets[i + 1]], want, atol=1e-10)


def test_ndbspline_batch_equals_each_spline():
    rng = np.random.default_rng(8)
    ts, cs, xis = [], [], []
    for _ in range(9):
        t = tuple(np.r_[[0.0] * 4, np.sort(rng.uniform(0, 3, int(rng.integers(1, 6)))),
                        [3.0] * 4] for _ in range(2))
        ts.append(t)
        cs.append(rng.normal(size=tuple(len(ta) - 4 for ta in t)))
        xis.append(rng.uniform(-0.5, 3.5, (int(rng.integers(0, 30)), 2)))
    batch = G.NdBSplines(ts, cs, 3)
    for nu in (None, (1, 2)):
        got, offsets = batch(xis, nu=nu)
        for i in range(len(ts)):
            want = S.NdBSpline(ts[i], cs[i], 3)(xis[i], nu=nu)
            np.testing.assert_allclose(got[offsets[i]:offsets[i + 1]], want, atol=1e-12)
    with pytest.raises(ValueError, match=r"splines\[1\]"):
        G.NdBSplines([ts[0], (ts[0][0][::-1], ts[0][1])], [cs[0], cs[0]], 3)
    with pytest.raises(ValueError, match=r"xis\[0\]"):
        batch([np.zeros((3, 3)), *xis[1:]])


def test_bicubic_on_a_gpu_context_within_the_surface_promise():
    import splinegpu

    try:
        gpu = splinegpu.Context("gpu")
    except RuntimeError:
        pytest.skip("no adapter")
    rng = np.random.default_rng(9)
    t = (np.r_[0, 0, 0, 0, np.sort(rng.uniform(0, 4, 5)), 4, 4, 4, 4.0],
         np.r_[-1, -1, -1, -1, np.sort(rng.uniform(-1, 2, 3)), 2, 2, 2, 2.0])
    c = 1e3 + rng.normal(size=(9, 7, 3))
    xi = np.stack([rng.uniform(0, 4, 2000), rng.uniform(-1, 2, 2000)], axis=-1)
    cpu, dev = G.NdBSpline(t, c, 3), G.NdBSpline(t, c, 3, context=gpu)
    scale = np.abs(c).max()
    for nu in (None, (1, 0), (1, 1), (0, 2)):
        got, want = dev(xi, nu=nu), cpu(xi, nu=nu)
        assert got.dtype == np.float32 and got.shape == want.shape == (2000, 3)
        # The contract's surface promise, bounded from above: positions 1e-5 of the spread
        # (a few units here) plus 4 ulp of 1e3; derivatives 1e-4 of their size (measured:
        # 3e-5, 1e-5, 1e-4, 2.5e-4 against bounds 3e-4, 1.1e-3, 1.2e-2, 3.3e-2).
        bound = 1e-5 * 10 + 4 * np.spacing(np.float32(2e3)) if nu is None else \
            1e-4 * np.abs(want).max()
        np.testing.assert_allclose(got, want, rtol=0, atol=bound)
    # Outside the base interval, a derivative the surface has no plane for, 3-D: the CPU.
    assert dev(xi - 5.0).dtype == np.float64
    assert dev(xi, nu=(2, 1)).dtype == np.float64
    rgi = G.RegularGridInterpolator((np.arange(9.0), np.arange(7.0)), c, method="cubic",
                                    context=gpu)
    pts = inside(rng, (np.arange(9.0), np.arange(7.0)), 500)
    np.testing.assert_allclose(rgi(pts), scipy_rgi((np.arange(9.0), np.arange(7.0)), c,
                                                   "cubic")(pts), atol=1e-4 * scale)
    batch = G.RegularGridInterpolators([(np.arange(9.0), np.arange(7.0))] * 3, [c] * 3,
                                       method="cubic", context=gpu)
    values, offsets = batch([pts, pts[:10], pts[:0]])
    assert values.dtype == np.float32 and list(offsets) == [0, 500, 510, 510]
    np.testing.assert_allclose(values[:500], rgi(pts), atol=1e-6 * scale)
