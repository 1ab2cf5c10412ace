"""B-splines of any degree against SciPy 1.17: make_interp_spline for k = 0 to 5 with SciPy's
knots, ends and periodic splines, a given t, BSpline.design_matrix, insert_knot,
from_power_basis and basis_element, PPoly.from_spline and from_bernstein_basis. Knots equal
SciPy's bit for bit, coefficients and values within 1e-10 of the largest."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import interpolate

import splinegpu.interpolate as si


def uneven(rng, n):
    """n increasing x with neighbouring spacings up to 1e3 apart."""
    return np.cumsum(10 ** rng.uniform(-1.5, 1.5, n))


def close(ours, theirs, scale=None):
    scale = max(1.0, float(np.max(np.abs(theirs)))) if scale is None else scale
    np.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-10 * scale)


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(0, 5), st.sampled_from(["default", "periodic",
                                                                        "ends"]),
       st.sampled_from([(), (3,), (2, 2)]))
def test_make_interp_spline_of_any_degree_is_scipys(seed, k, ends, trailing):
    rng = np.random.default_rng(seed)
    x = uneven(rng, int(rng.integers(k + 2, 14)))
    y = rng.normal(size=(len(x), *trailing))
    bc = None
    if ends == "periodic":
        if k < 1:
            return
        y[-1] = y[0]
        bc = "periodic"
    elif ends == "ends":
        if k < 3 or k % 2 == 0:
            return
        # (k - 1) / 2 derivatives at each end, of y's trailing shape.
        count = (k - 1) // 2
        left = [(o, rng.normal(size=trailing)) for o in range(1, count + 1)]
        right = [(o, rng.normal(size=trailing)) for o in range(1, count + 1)]
        bc = (left, right)
    ours = si.make_interp_spline(x, y, k=k, bc_type=bc)
    theirs = interpolate.make_interp_spline(x, y, k=k, bc_type=bc)
    np.testing.assert_array_equal(ours.t, theirs.t)
    close(ours.c, theirs.c)
    q = np.concatenate([x, rng.uniform(x[0], x[-1], 20)])
    for nu in range(min(k, 2) + 1):
        close(ours(q, nu), theirs(q, nu), float(np.max(np.abs(theirs(q, nu)))) + 1)


def test_make_interp_spline_takes_a_given_t_and_complex_values():
    rng = np.random.default_rng(4)
    x = uneven(rng, 12)
    y = rng.normal(size=12) + 1j * rng.normal(size=12)
    t = interpolate.make_interp_spline(x, y.real, k=3).t
    for k, knots in ((3, t), (2, np.r_[[x[0]] * 3, (x[1:-2] + x[2:-1]) / 2, [x[-1]] * 3])):
        ours = si.make_interp_spline(x, y, k=k, t=knots)
        theirs = interpolate.make_interp_spline(x, y, k=k, t=knots)
        close(ours.c, theirs.c)
    with pytest.raises(TypeError):
        si.make_interp_spline(x, y, k="cubic")


@pytest.mark.parametrize("extrapolate", [False, True, "periodic"])
@pytest.mark.parametrize("k", [0, 1, 2, 3, 5])
def test_design_matrix_is_scipys(k, extrapolate):
    rng = np.random.default_rng(k)
    t = np.sort(np.r_[rng.uniform(0, 10, 12 + k), [0] * k, [10] * k])
    n = len(t) - k - 1
    lo, hi = t[k], t[n]
    x = rng.uniform(lo, hi, 40) if extrapolate is False else rng.uniform(lo - 3, hi + 3, 40)
    ours = si.BSpline.design_matrix(x, t, k, extrapolate)
    theirs = interpolate.BSpline.design_matrix(x, t, k, extrapolate)
    assert ours.shape == theirs.shape
    np.testing.assert_array_equal(ours.indices, theirs.indices)
    close(ours.toarray(), theirs.toarray())
    if extrapolate is False:
        with pytest.raises(ValueError, match="Out of bounds"):
            si.BSpline.design_matrix(np.r_[x, hi + 1], t, k)


@pytest.mark.parametrize("periodic", [False, True])
@pytest.mark.parametrize("at", [0.0, 0.3, 2.0, 4.5, 6.9, 7.0])
def test_insert_knot_is_scipys(at, periodic):
    x = np.arange(8.0)
    y = np.sin(x)[:, None] ** 3 * np.array([1.0, 2.0])
    if periodic:
        t, c, k = interpolate.splrep(x, np.sin(x) ** 3, k=3)
        ours = si.BSpline(t, c, k, extrapolate="periodic").insert_knot(at, 2)
        theirs = interpolate.BSpline(t, c, k, extrapolate="periodic").insert_knot(at, 2)
    else:
        ours = si.make_interp_spline(x, y, k=3).insert_knot(at, 2)
        theirs = interpolate.make_interp_spline(x, y, k=3).insert_knot(at, 2)
    np.testing.assert_allclose(ours.t, theirs.t, rtol=0, atol=1e-15)
    close(ours.c, theirs.c)


@pytest.mark.parametrize("bc", ["not-a-knot", "natural", "clamped", "periodic"])
def test_from_power_basis_is_scipys(bc):
    rng = np.random.default_rng(7)
    x = uneven(rng, 10)
    y = rng.normal(size=10)
    if bc == "periodic":
        y[-1] = y[0]
    ours = si.BSpline.from_power_basis(si.CubicSpline(x, y, bc_type=bc), bc_type=bc)
    theirs = interpolate.BSpline.from_power_basis(interpolate.CubicSpline(x, y, bc_type=bc),
                                                  bc_type=bc)
    np.testing.assert_array_equal(ours.t, theirs.t)
    close(ours.c, theirs.c)
    with pytest.raises(NotImplementedError):
        si.BSpline.from_power_basis(si.PchipInterpolator(x, y))


def test_basis_element_and_a_subclass_keep_their_class():
    class Mine(si.BSpline):
        pass

    for t in ([0, 1, 2], [0, 1, 1, 3], [0, 0.5, 2, 2.5, 4]):
        ours, theirs = si.BSpline.basis_element(t), interpolate.BSpline.basis_element(t)
        np.testing.assert_array_equal(ours.t, theirs.t)
        q = np.linspace(-1, 5, 31)
        close(ours(q), theirs(q))
        assert type(Mine.basis_element(t)) is Mine
        assert type(Mine.basis_element(t).derivative()) is Mine


def test_ppoly_from_a_spline_and_from_bernstein_is_scipys():
    rng = np.random.default_rng(3)
    x = uneven(rng, 15)
    tck = interpolate.splrep(x, np.sin(x / x[-1] * 9), k=3)
    for source in (tck, interpolate.BSpline(*tck), si.BSpline(*tck)):
        ours = si.PPoly.from_spline(source)
        theirs = interpolate.PPoly.from_spline(tck)
        np.testing.assert_array_equal(ours.x, theirs.x)
        close(ours.c, theirs.c, float(np.max(np.abs(theirs.c))))
        r = ours.roots()
        np.testing.assert_allclose(r[(r >= x[0]) & (r <= x[-1])], interpolate.sproot(tck),
                                   rtol=0, atol=1e-12 * x[-1])
    bp = interpolate.BPoly(rng.normal(size=(5, 4)), [0.0, 1.0, 3.0, 3.5, 6.0])
    ours, theirs = si.PPoly.from_bernstein_basis(bp), interpolate.PPoly.from_bernstein_basis(bp)
    close(ours.c, theirs.c)
    with pytest.raises(TypeError, match="BPoly"):
        si.PPoly.from_bernstein_basis(ours)


def test_bsplines_unpack_as_fitpacks_tck():
    x = np.linspace(0, 5, 12)
    spline = si.make_interp_spline(x, np.cos(x))
    q = np.linspace(-1, 6, 29)
    close(interpolate.splev(q, spline), spline(q))
    close(interpolate.splint(0.5, 4.0, spline), spline.integrate(0.5, 4.0))
    t, c, k = spline
    assert len(c) == len(t) and k == 3


def test_a_nan_coefficient_reaches_only_its_support():
    t = np.r_[[0.0] * 4, 1, 2, 3, 4, 5, [6.0] * 4]
    c = np.arange(9.0)
    c[4] = np.nan
    q = np.linspace(0, 6, 61)
    ours, theirs = si.BSpline(t, c, 3)(q), interpolate.BSpline(t, c, 3)(q)
    np.testing.assert_array_equal(np.isnan(ours), np.isnan(theirs))
    close(ours[~np.isnan(ours)], theirs[~np.isnan(theirs)])
