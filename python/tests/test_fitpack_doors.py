"""The legacy FITPACK doors (splrep, splprep, UnivariateSpline) against SciPy's own, which run
FITPACK's curfit, parcur, percur and clocur: the same knots (bit for bit), coefficients within
1e-10 of the data's range, fp within 1e-10 relative, the same ier, class and warnings. A grid
over n (10 to 10,000 points of sin x + N(0, 0.1^2)), s (0.1 to 10 n sigma^2), k, weights,
room for knots (nest too small included), periodic and parametric, and a property test
drawing all of them at random.

The make_splrep / make_splprep doors are SciPy's Python re-derivation and are held to it in
test_fitting.py."""

import warnings

import numpy as np
import pytest
import scipy.interpolate as S
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.interpolate import _dfitpack

import splinegpu.interpolate as G

SIGMA = 0.1


def noisy(n: int, seed: int, d: int = 1):
    rng = np.random.default_rng(seed)
    x = np.sort(rng.uniform(0, 10, n))
    y = [np.sin(x * (j + 1)) + rng.normal(0, SIGMA, n) for j in range(d)]
    return x, (y[0] if d == 1 else y), rng


def same_fit(ours, theirs, scale: float):
    """(t, c, fp, ier) of two fits: t equal, c within 1e-10 of scale, fp within 1e-10."""
    (t, c, fp, ier), (t2, c2, fp2, ier2) = ours, theirs
    np.testing.assert_array_equal(t, t2)
    c, c2 = np.asarray(c, dtype=float), np.asarray(c2, dtype=float)
    np.testing.assert_allclose(c, c2, rtol=0, atol=1e-10 * scale)
    assert abs(fp - fp2) <= 1e-10 * max(fp2, 1e-300), (fp, fp2)
    assert ier == ier2


def splrep_pair(x, y, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        (t, c, k), fp, ier, _ = G.splrep(x, y, full_output=1, **kw)
        (t2, c2, _), fp2, ier2, _ = S.splrep(x, y, full_output=1, **kw)
    n = len(t2) - k - 1
    return (t, c[:n], fp, ier), (t2, c2[:n], fp2, ier2)


@pytest.mark.parametrize("n", [10, 31, 100, 300, 1000, 10000])
@pytest.mark.parametrize("k", [1, 3, 5])
def test_splrep_is_fitpacks_curfit(n, k):
    x, y, rng = noisy(n, n + k)
    # 10,000 points at 0.1 n sigma^2 place ~2,000 knots in ~40 s (FITPACK's and ours alike).
    for factor in (0.1, 0.3, 1.0, 3.0, 10.0) if n < 10000 else (1.0, 10.0):
        s = factor * n * SIGMA ** 2
        ours, theirs = splrep_pair(x, y, k=k, s=s)
        same_fit(ours, theirs, np.ptp(y))
        w = rng.uniform(0.5, 2.0, n)
        ours, theirs = splrep_pair(x, y, w=w, xb=x[0] - 0.5, k=k, s=s)
        same_fit(ours, theirs, np.ptp(y))


def test_the_issues_300_points_at_s_2():
    """The report: 300 noisy points at s = 2.0 stopped at 96 knots against SciPy's 116, the
    values 4% of the data's range apart (make_splrep's bookkeeping)."""
    for seed in range(4):
        x, y, _ = noisy(300, seed)
        ours, theirs = splrep_pair(x, y, s=2.0)
        same_fit(ours, theirs, np.ptp(y))
        one, two = G.UnivariateSpline(x, y, s=2.0), S.UnivariateSpline(x, y, s=2.0)
        np.testing.assert_array_equal(one.get_knots(), two.get_knots())
        np.testing.assert_allclose(one(x), two(x), rtol=0, atol=1e-10)


@pytest.mark.parametrize("n", [10, 40, 300, 3000])
@pytest.mark.parametrize("d", [2, 3])
def test_splprep_is_fitpacks_parcur(n, d):
    _, points, _ = noisy(n, n + d, d)
    for factor in (0.1, 1.0, 10.0):
        for k in (1, 3, 5):
            for nest in (None, max(2 * k + 3, n // 10)):
                s = factor * n * d * SIGMA ** 2
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    (tck, u), fp, ier, _ = G.splprep(points, s=s, k=k, nest=nest,
                                                     full_output=1)
                    (tck2, u2), fp2, ier2, _ = S.splprep(points, s=s, k=k, nest=nest,
                                                         full_output=1)
                np.testing.assert_array_equal(u, u2)
                same_fit((tck[0], tck[1], fp, ier), (tck2[0], tck2[1], fp2, ier2), 2.0)


@pytest.mark.parametrize("n", [20, 109, 300, 2000])
@pytest.mark.parametrize("k", [1, 3, 4])
def test_univariate_spline_is_fitpacks_to_its_class(n, k):
    """fpcurf0's room for m // 2 knots, then for all (ier 1), set_smoothing_factor's chain
    (curfit's iopt = 1) up and down in s, the class FITPACK's ier gives and the residual."""
    x, y, _ = noisy(n, n * k)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ours, theirs = G.UnivariateSpline(x, y, k=k, s=n * 0.01), \
            S.UnivariateSpline(x, y, k=k, s=n * 0.01)
        for s in (n * 0.003, n * 0.03, n * 0.001, n * 0.5, n * 0.0002, None):
            np.testing.assert_array_equal(ours.get_knots(), theirs.get_knots())
            np.testing.assert_allclose(ours.get_coeffs(), theirs.get_coeffs(), rtol=0,
                                       atol=1e-10 * np.ptp(y))
            assert type(ours).__name__ == type(theirs).__name__
            assert abs(ours.get_residual() - theirs.get_residual()) <= \
                1e-10 * theirs.get_residual()
            if s is not None:
                ours.set_smoothing_factor(s)
                theirs.set_smoothing_factor(s)


def test_univariate_spline_warns_and_changes_class_as_scipys():
    """The class FITPACK's ier gives (-2 the polynomial, -1 interpolation) and the warnings
    for ier 2 and 3 (s far too small), word for word."""
    x, y, _ = noisy(50, 1)
    for s, k, name, warned in ((1e6, 3, "LSQUnivariateSpline", 0),
                               (0.0, 3, "InterpolatedUnivariateSpline", 0),
                               (1e-12, 3, "UnivariateSpline", 1),
                               (1e-30, 1, "UnivariateSpline", 1),
                               (1e-30, 5, "UnivariateSpline", 1),
                               (0.3, 3, "UnivariateSpline", 0)):
        with warnings.catch_warnings(record=True) as ours_said:
            warnings.simplefilter("always")
            ours = G.UnivariateSpline(x, y, s=s, k=k)
        with warnings.catch_warnings(record=True) as theirs_said:
            warnings.simplefilter("always")
            theirs = S.UnivariateSpline(x, y, s=s, k=k)
        assert type(ours).__name__ == type(theirs).__name__ == name
        said = [str(w.message) for w in ours_said]
        assert said == [str(w.message) for w in theirs_said] and len(said) == warned
        np.testing.assert_allclose(ours.get_coeffs(), theirs.get_coeffs(), rtol=0, atol=1e-9)


def test_far_apart_weights_keep_fitpacks_knots(far_apart_weights):
    """SciPy's gh-1375 data: weights 1e12 against 1e2 to 1e3."""
    x, y, w = far_apart_weights
    for s in (5.0, 13.0):
        ours, theirs = splrep_pair(x, y, w=w, s=s)
        np.testing.assert_array_equal(ours[0], theirs[0])
        np.testing.assert_allclose(ours[1], theirs[1], rtol=0, atol=1e-8)


def test_task_1_goes_on_as_curfit_with_iopt_1():
    """splrep's task=1 against FITPACK's fpcurf with iopt = 1 (SciPy's fpcurf1, which
    carries the knot count; SciPy 1.17's own splrep(task=1) raises UnboundLocalError)."""
    for n, k in ((50, 3), (500, 2)):
        x, y, _ = noisy(n, n + k)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            data = _dfitpack.fpcurf0(x, y, k, s=n * 0.02, nest=n + k + 1)
            G.splrep(x, y, k=k, s=n * 0.02)
            for s in (n * 0.01, n * 0.005, n * 0.05, n * 0.0001, n * 0.2):
                data = _dfitpack.fpcurf1(*data[:6], s, *data[7:])
                count, t, c, fp, ier = data[7], data[8], data[9], data[10], data[13]
                (t2, c2, _), fp2, ier2, _ = G.splrep(x, y, k=k, s=s, task=1, full_output=1)
                same_fit((t2, c2[:count - k - 1], fp2, ier2),
                         (t[:count], c[:count - k - 1], fp, ier), np.ptp(y))
    G.splrep(x, y, t=[2.0, 5.0])
    with pytest.raises(TypeError, match="task must be -1, 0 or 1"):
        G.splrep(x, y, task=2)


def test_where_fitpacks_knot_placement_fails_the_fit_still_meets_s():
    """SciPy's gh-3691 data (spikes on zeros, k = 1): every interval with data inside has no
    residual, so FITPACK's fpknot places no knot but counts one, and SciPy returns NaN
    coefficients with a warning. Here the search stops there: finite, fp = s within
    FITPACK's tolerance."""
    y = np.array([0., 0., 0., 0., 0., 10.9, 0., 11., 0., 0., 0., 10.9, 0., 0., 0., 0., 0., 0.,
                  10.9, 0., 0., 0., 11., 0., 0., 0., 10.9, 0., 0., 0., 10.5, 0., 0., 0., 10.7,
                  0., 0., 0., 11., 0., 0., 0., 0., 0., 0., 10.9, 0., 0., 10.7, 0., 0., 0., 10.6,
                  0., 0., 0., 10.5, 0., 0., 10.7, 0., 0., 10.5, 0., 0., 11.5, 0., 0., 0., 10.7,
                  0., 0., 10.7, 0., 0., 10.9, 0., 0., 10.8, 0., 0., 0., 10.7, 0., 0., 10.6, 0.,
                  0., 0., 10.4, 0., 0., 10.6, 0., 0., 10.5, 0., 0., 0., 10.7, 0., 0., 0., 10.4,
                  0., 0., 0., 10.8, 0.])
    spline = G.UnivariateSpline(np.arange(109.0), y, k=1)
    assert np.all(np.isfinite(spline.get_coeffs()))
    assert abs(spline.get_residual() - 109) <= 109e-3


def periodic_data(n: int, seed: int):
    rng = np.random.default_rng(seed)
    x = np.sort(rng.uniform(0, 10, n))
    x[0], x[-1] = 0.0, 10.0
    y = np.sin(x * np.pi / 5) + rng.normal(0, SIGMA, n)
    y[-1] = y[0]
    points = np.array([np.cos(x * np.pi / 5), np.sin(x * 2 * np.pi / 5)]) + \
        rng.normal(0, SIGMA / 2, (2, n))
    points[:, -1] = points[:, 0]
    return x, y, points


@pytest.mark.parametrize("n", [8, 15, 40, 300, 2000])
@pytest.mark.parametrize("k", [1, 2, 3, 5])
def test_periodic_doors_are_fitpacks_percur_and_clocur(n, k):
    """splrep(per=1) against percur, splprep(per=1) against clocur (which close the curve)."""
    x, y, points = periodic_data(n, n * k)
    for factor in (0.05, 0.3, 1.0, 3.0, 30.0):
        s = factor * n * SIGMA ** 2
        ours, theirs = splrep_pair(x, y, k=k, s=s, per=1)
        same_fit(ours, theirs, 2.0)
        for nest in (None, max(2 * k + 3, n // 4)):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                (tck, u), fp, ier, _ = G.splprep(list(points), k=k, s=s, per=1, nest=nest,
                                                 full_output=1)
                (tck2, u2), fp2, ier2, _ = S.splprep(list(points), k=k, s=s, per=1, nest=nest,
                                                     full_output=1)
            np.testing.assert_array_equal(u, u2)
            same_fit((tck[0], tck[1], fp, ier), (tck2[0], tck2[1], fp2, ier2), 2.0)


@settings(max_examples=60, deadline=None, derandomize=True,
          suppress_health_check=list(HealthCheck))
@given(n=st.integers(6, 3000), factor=st.floats(0.05, 20.0), k=st.integers(1, 5),
       seed=st.integers(0, 2 ** 32 - 1), weighted=st.booleans(), d=st.integers(1, 3),
       nest_share=st.one_of(st.none(), st.floats(0.02, 1.0)), per=st.booleans())
def test_any_draw_is_fitpacks(n, factor, k, seed, weighted, d, nest_share, per):
    """Random data, s, degree, weights, coordinates, room for knots and periodicity: splrep
    (d = 1) or splprep (d > 1) gives FITPACK's knots, coefficients, fp and ier."""
    if n <= k + 1:
        return
    x, y, rng = noisy(n, seed, d)
    if per:
        # The last point stands for the first (splrep's y, splprep closes the curve itself).
        if d == 1:
            y[-1] = y[0]
    w = rng.uniform(0.2, 5.0, n) if weighted else None
    s = factor * n * d * SIGMA ** 2
    if d == 1:
        ours, theirs = splrep_pair(x, y, w=w, k=k, s=s, per=int(per))
        same_fit(ours, theirs, np.ptp(y))
        return
    nest = None if nest_share is None else max(2 * k + 3, int(nest_share * n))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        (tck, u), fp, ier, _ = G.splprep(y, w=w, s=s, k=k, nest=nest, per=int(per),
                                         full_output=1)
        (tck2, u2), fp2, ier2, _ = S.splprep(y, w=w, s=s, k=k, nest=nest, per=int(per),
                                             full_output=1)
    np.testing.assert_array_equal(u, u2)
    same_fit((tck[0], tck[1], fp, ier), (tck2[0], tck2[1], fp2, ier2), 2.0)


def test_rect_bivariate_smoothing_is_fitpacks_regrid():
    """RectBivariateSpline with s > 0 against SciPy's regrid on random grids (sizes 6 to 25,
    degrees 1 to 5 in each direction, s from 0.3 to 3 times the noise's sum of squares,
    maxit 1 and 20): the same knots bit for bit, fp within 1e-10, the same error where SciPy
    raises, values on and off the grid within 1e-9 of SciPy's, knots left out of order by
    regrid included (evaluated as FITPACK's bispev). Smaller s drive SciPy's Fortran to
    interpolation in one direction, where it writes past its arrays and can crash the
    interpreter, so they are not drawn here."""
    rng = np.random.default_rng(17)
    compared = 0
    for _ in range(150):
        mx, my = (int(v) for v in rng.integers(6, 26, 2))
        kx, ky = (int(v) for v in rng.integers(1, 6, 2))
        if mx <= kx or my <= ky:
            continue
        x = np.sort(rng.uniform(0, 4, mx))
        y = np.sort(rng.uniform(-1, 3, my))
        z = np.sin(x[:, None]) * np.cos(y[None, :]) + rng.normal(0, SIGMA, (mx, my))
        s = float(rng.uniform(0.3, 3.0)) * mx * my * SIGMA ** 2
        maxit = int(rng.choice([1, 20]))
        try:
            theirs = S.RectBivariateSpline(x, y, z, kx=kx, ky=ky, s=s, maxit=maxit)
        except ValueError as e:
            with pytest.raises(ValueError) as ours_error:
                G.RectBivariateSpline(x, y, z, kx=kx, ky=ky, s=s, maxit=maxit)
            assert str(e).split("\n")[1] in str(ours_error.value)
            continue
        ours = G.RectBivariateSpline(x, y, z, kx=kx, ky=ky, s=s, maxit=maxit)
        for a, b in zip(ours.get_knots(), theirs.get_knots()):
            np.testing.assert_array_equal(a, b)
        assert abs(ours.fp - theirs.fp) <= 1e-10 * theirs.fp
        xi, yi = np.linspace(-0.5, 4.5, 23), np.linspace(-1.5, 3.5, 19)
        want = theirs(xi, yi)
        np.testing.assert_allclose(ours(xi, yi), want, rtol=0,
                                   atol=1e-9 * max(1.0, np.abs(want).max()))
        compared += 1
    assert compared > 80, compared
    # regrid leaves knots out of order here (30 x 40 points, s 0.4 of the noise's sum).
    rng = np.random.default_rng(0)
    x, y = np.sort(rng.uniform(0, 4, 30)), np.sort(rng.uniform(0, 3, 40))
    z = np.sin(x[:, None]) * np.cos(y) + rng.normal(0, SIGMA, (30, 40))
    ours, theirs = G.RectBivariateSpline(x, y, z, s=5.0), S.RectBivariateSpline(x, y, z, s=5.0)
    assert any(np.any(np.diff(t) < 0) for t in theirs.get_knots())
    for a, b in zip(ours.get_knots(), theirs.get_knots()):
        np.testing.assert_array_equal(a, b)
    xi, yi = np.linspace(-0.5, 4.5, 37), np.linspace(-0.2, 3.3, 41)
    for dx, dy in ((0, 0), (1, 0), (0, 1), (1, 2), (2, 2)):
        want = theirs(xi, yi, dx, dy)
        np.testing.assert_allclose(ours(xi, yi, dx, dy), want, rtol=0,
                                   atol=1e-10 * np.abs(want).max())
    assert abs(ours.integral(0.5, 3, 0.2, 2.5) - theirs.integral(0.5, 3, 0.2, 2.5)) < 1e-12


def test_splint_integrates_as_fpintb():
    """splint on SciPy's own tcks, any degree and limits (reversed, past the ends): the value
    within 1e-13 relative and full_output's integrals of the B-splines (FITPACK's fpintb)."""
    rng = np.random.default_rng(8)
    for _ in range(60):
        n, k = int(rng.integers(8, 40)), int(rng.integers(1, 6))
        x, y, _ = noisy(n, int(rng.integers(1 << 30)))
        tck = S.splrep(x, y, k=k, s=float(rng.choice([0.0, 0.05 * n])))
        a, b = (float(v) for v in rng.uniform(-1, 11, 2))
        ours, theirs = G.splint(a, b, tck, full_output=1), S.splint(a, b, tck, full_output=1)
        assert abs(ours[0] - theirs[0]) <= 1e-13 * max(1.0, abs(theirs[0]))
        np.testing.assert_allclose(ours[1], theirs[1][:len(ours[1])], rtol=1e-13, atol=1e-15)
    with pytest.raises(ValueError, match=">=n-k-1"):
        G.splint(0, 1, (np.ones(10), np.ones(5), 3))
