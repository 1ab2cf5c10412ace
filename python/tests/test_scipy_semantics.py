"""What SciPy users rely on without thinking, against SciPy itself: every bc_type form (second
derivative ends, mixed ends, pairs of names, periodic on 2 points), extrapolation (True, False,
"periodic", the spline's default and a call's override), the third derivative, read-only
copies of x and c, and splines and contexts that pickle and deep-copy."""

import copy
import pickle

import numpy as np
import pytest

import splinegpu

interpolate = pytest.importorskip("scipy.interpolate")

BC_TYPES = ["not-a-knot", "natural", "clamped", "periodic", ((1, 0.5), (1, -2.0)),
            ((2, 0.0), (2, 0.0)), ((2, 3.0), (2, -1.5)), ((1, 0.5), (2, 4.0)),
            ((2, -2.0), (1, 1.0)), ("natural", "clamped"), ("clamped", "not-a-knot"),
            ("not-a-knot", (2, 1.0)), ("natural", "not-a-knot"), ((1, 2.0), "natural")]


def spline_data(bc, shape, seed):
    """Uneven x (neighbouring spacings up to 1e3 apart) and y of `shape` trailing axes."""
    rng = np.random.default_rng(seed)
    h = 10.0 ** rng.uniform(-1.5, 1.5, 11)
    x = np.concatenate([[-3.0], -3.0 + np.cumsum(h)])
    y = rng.uniform(-2, 2, (len(x), *shape))
    if bc == "periodic":
        y[-1] = y[0]
    return x, y


def queries(x, rng):
    """Inside, at the knots and ends, just outside (1e-14 past the ends), far outside on both
    sides (up to the range again), and NaN."""
    lo, hi = x[0], x[-1]
    span = hi - lo
    return np.concatenate([
        rng.uniform(lo, hi, 40), x, [lo - 1e-14 * span, hi + 1e-14 * span, np.nan],
        rng.uniform(lo - span, lo, 10), rng.uniform(hi, hi + span, 10),
    ])


def assert_scipy(got, want, what):
    """Equal NaN positions; elsewhere within 1e-10 of the largest value (far extrapolation
    multiplies the coefficients' last-bit differences by up to the cube of the distance)."""
    assert got.shape == want.shape, what
    scale = np.nanmax(np.abs(want)) if np.isfinite(want).any() else 1.0
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-10 * max(scale, 1e-300),
                               equal_nan=True, err_msg=what)


@pytest.mark.parametrize("bc", BC_TYPES, ids=str)
@pytest.mark.parametrize("shape,axis", [((), 0), ((2, 3), 0), ((2, 3), -1)])
def test_extrapolation_and_every_derivative_match_scipy(bc, shape, axis):
    x, y = spline_data(bc, shape, seed=len(str(bc)) + len(shape))
    if isinstance(bc, tuple):
        # SciPy wants the end values in y's trailing shape (as ours does).
        bc = tuple(end if isinstance(end, str) else (end[0], np.full(shape, end[1]))
                   for end in bc)
    y = np.moveaxis(y, 0, axis)
    q = queries(x, np.random.default_rng(3))
    for extrapolate in (None, True, False, "periodic"):
        ours = splinegpu.CubicSpline(x, y, axis=axis, bc_type=bc, extrapolate=extrapolate)
        theirs = interpolate.CubicSpline(x, y, axis=axis, bc_type=bc, extrapolate=extrapolate)
        assert ours.extrapolate == theirs.extrapolate
        for nu in range(4):
            assert_scipy(ours(q, nu), theirs(q, nu), f"{bc}, {extrapolate}, nu={nu}")
            assert_scipy(ours.derivative(nu)(q) if nu else ours(q), theirs.derivative(nu)(q)
                         if nu else theirs(q), f"derivative({nu}), {bc}, {extrapolate}")
            # A call's own extrapolate overrides the spline's.
            for per_call in (True, False, "periodic"):
                assert_scipy(ours(q, nu, extrapolate=per_call),
                             theirs(q, nu, extrapolate=per_call),
                             f"{bc}, {extrapolate}, call {per_call}, nu={nu}")


def test_a_scalar_and_an_empty_x_outside_the_knots():
    x, y = spline_data("natural", (), 5)
    ours = splinegpu.CubicSpline(x, y, bc_type="natural")
    theirs = interpolate.CubicSpline(x, y, bc_type="natural")
    for q in (x[-1] + 1e-14, x[0] - 3.0, float("nan")):
        got, want = ours(q), theirs(q)
        assert got.shape == want.shape == ()
        assert_scipy(got, want, f"x = {q}")
    assert ours(np.array([]), extrapolate=False).shape == (0,)


def test_extrapolation_on_the_gpu_keeps_the_promise_inside_and_is_exact_outside(gpu):
    x, y = spline_data("not-a-knot", (3,), 9)
    q = queries(x, np.random.default_rng(4))
    theirs = interpolate.CubicSpline(x, y)
    on_gpu = splinegpu.CubicSpline(x, y, context=gpu)
    for nu in range(4):
        got = on_gpu(q, nu)
        assert got.dtype == np.float32
        want = theirs(q, nu)
        # f32 inside (the promise, about 1e-5 of the scale); outside, f64 cast to f32.
        scale = np.nanmax(np.abs(want))
        np.testing.assert_allclose(got, want, rtol=0, atol=2e-5 * scale, equal_nan=True,
                                   err_msg=f"nu={nu}")


def test_bad_extrapolate_and_nu_are_refused_by_name():
    x = np.arange(5.0)
    with pytest.raises(ValueError, match="extrapolate: must be True, False or 'periodic'"):
        splinegpu.CubicSpline(x, x, extrapolate="wrap")
    spline = splinegpu.CubicSpline(x, x)
    with pytest.raises(ValueError, match="extrapolate"):
        spline(1.0, extrapolate="clip")
    with pytest.raises(ValueError, match="nu: must be an integer"):
        spline(1.0, nu=-1)
    # Past the degree a derivative is zero, as SciPy's (a bool nu is an order too).
    assert spline(1.0, nu=4) == 0.0 and spline.derivative(2)(1.0, nu=2) == 0.0
    assert spline(1.5, nu=True) == spline(1.5, nu=1)


def test_x_and_c_are_copies_that_refuse_writes():
    x, y = spline_data("natural", (2,), 6)
    spline = splinegpu.CubicSpline(x, y)
    before = spline(x)
    x[3] += 0.5
    y[:] = 0
    assert spline.x[3] != x[3]
    np.testing.assert_array_equal(spline(spline.x), before)
    with pytest.raises(ValueError, match="read-only"):
        spline.c[0, 0, 0] = 1.0
    with pytest.raises(ValueError, match="read-only"):
        spline.x[0] = -10.0


@pytest.mark.parametrize("bc", BC_TYPES, ids=str)
def test_splines_and_contexts_pickle_and_deep_copy_bit_for_bit(bc, cpu):
    x, y = spline_data(bc, (2,), 7)
    q = queries(x, np.random.default_rng(8))
    bc = bc if isinstance(bc, str) else tuple(
        end if isinstance(end, str) else (end[0], np.full(2, end[1])) for end in bc)
    spline = splinegpu.CubicSpline(x, y * (1 + 2j), bc_type=bc, extrapolate=False, context=cpu)
    for again in (pickle.loads(pickle.dumps(spline)), copy.deepcopy(spline)):
        assert again.extrapolate is False and again.axis == 0
        assert again.context.backend == "cpu"
        np.testing.assert_array_equal(again.x, spline.x)
        np.testing.assert_array_equal(again.c, spline.c)
        for nu in range(4):
            np.testing.assert_array_equal(again(q, nu), spline(q, nu))
    batch = splinegpu.CubicSplines([x, x[:8]], [y, y[:8]], bc_type="natural")
    again = pickle.loads(pickle.dumps(batch))
    assert len(again) == 2 and again.context is None
    inside = np.random.default_rng(9).uniform(x[0], x[7], 30)
    for a, b in zip(again([inside, inside]), batch([inside, inside])):
        np.testing.assert_array_equal(a, b)
    assert pickle.loads(pickle.dumps(cpu)).backend == "cpu"


def test_a_damaged_pickle_is_refused_with_the_part_named():
    spline = splinegpu.CubicSpline(np.arange(5.0), np.arange(5.0))
    restore, (cls, attributes, state) = spline.__reduce__()
    dim, knots, coeffs, extent = state[0]
    with pytest.raises(ValueError, match=r'curve 0: "knots" must be strictly increasing'):
        restore(cls, attributes, [(dim, knots[::-1].copy(), coeffs, extent)])
    with pytest.raises(ValueError, match=r'"coefficients" must have'):
        restore(cls, attributes, [(dim, knots, coeffs[:-1].copy(), extent)])


def test_small_periodic_and_mixed_splines_are_scipys():
    q = np.linspace(-1, 3, 41)
    cases = [
        ([0.0, 2.0], [1.5, 1.5], "periodic"),
        ([0.0, 2.0], [[1.0, -1.0], [1.0, -1.0]], "periodic"),
        ([0.0, 1.0], [0.0, 2.0], ((2, 1.0), (1, -3.0))),
        ([0.0, 1.0, 2.5], [0.0, 2.0, 1.0], ("not-a-knot", (2, 1.0))),
        ([0.0, 1.0], [0.0, 2.0], ("natural", "natural")),
    ]
    for x, y, bc in cases:
        ours, theirs = splinegpu.CubicSpline(x, y, bc_type=bc), \
            interpolate.CubicSpline(x, y, bc_type=bc)
        for nu in range(4):
            assert_scipy(ours(q, nu), theirs(q, nu), f"{x}, {bc}, nu={nu}")


def test_bad_ends_are_refused_by_name():
    x, y = np.arange(5.0), np.arange(5.0) ** 2
    for bc, message in [
        (("natural", "periodic"), "a pair of those but"),
        (((3, 0.0), (1, 0.0)), "order at an end must be 1 or 2, got 3"),
        (((2, np.nan), (1, 0.0)), r'"start_derivative" must be finite'),
        (((2, [1.0, 2.0]), (1, 0.0)), "bc_type"),
        (("natural",), "bc_type"),
    ]:
        with pytest.raises(ValueError, match=message):
            splinegpu.CubicSpline(x, y, bc_type=bc)
    with pytest.raises(ValueError, match="must end where they start"):
        splinegpu.CubicSpline([0.0, 1.0], [0.0, 1.0], bc_type="periodic")


def _raising_cases():
    """Inputs SciPy refuses, each a function of the module (SciPy's or ours) to call."""
    x = np.linspace(0, 10, 20)
    y = np.sin(x)
    xd, yd = np.array([0.0, 1.0, 1.0, 2.0, 3.0]), np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    grid = (np.linspace(0, 1, 7), np.linspace(0, 1, 8))
    cases = {
        "UnivariateSpline.derivatives outside the knots":
            lambda m: m.UnivariateSpline(x, y).derivatives(-1e-9),
        "UnivariateSpline called with nu > k": lambda m: m.UnivariateSpline(x, y)(x, nu=4),
        "UnivariateSpline called with nu < 0": lambda m: m.UnivariateSpline(x, y)(x, nu=-1),
        "splrep with an interior knot repeated": lambda m: m.splrep(x, y, t=[0.5] * 4),
    }
    for kind in ("zero", "slinear", 0, 1):
        cases[f"interp1d {kind!r} on a repeated x"] = (
            lambda m, kind=kind: m.interp1d(xd, yd, kind=kind)(0.5))
    for bad in (np.nan, np.inf):
        values = np.random.default_rng(0).normal(size=(7, 8))
        values[2, 3] = bad
        for method in ("slinear", "cubic", "quintic", "pchip", "cubic_legacy"):
            cases[f"RegularGridInterpolator {method} with {bad} in values"] = (
                lambda m, method=method, values=values:
                m.RegularGridInterpolator(grid, values, method=method)([[0.5, 0.5]]))
    return cases


@pytest.mark.parametrize("case", list(_raising_cases()))
def test_what_scipy_refuses_is_refused_with_its_exception(case):
    """Where SciPy raises, so does this package, with the same exception type (the message
    names the fault; SciPy's own words where it has some)."""
    import warnings

    import scipy.interpolate as scipy

    import splinegpu.interpolate as ours
    call = _raising_cases()[case]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(Exception) as theirs:
            call(scipy)
        with pytest.raises(theirs.type):
            call(ours)


def test_insert_is_scipys_on_tck_parametric_periodic_and_bsplines():
    """`insert` against SciPy's: the knots and coefficients of a tck (within its length: the
    padding past it is FITPACK's scratch), a parametric tck's list, per=1, and a BSpline in
    giving a BSpline out with the same values."""
    import scipy.interpolate as scipy

    import splinegpu.interpolate as ours
    x = np.linspace(0, 10, 12)
    cases = [(3.3, scipy.splrep(x, np.sin(x)), 0, 2),
             (0.4, scipy.splprep([np.cos(x), np.sin(x)], s=0)[0], 0, 1)]
    xp = np.linspace(0, 2 * np.pi, 20)
    yp = np.sin(xp)
    yp[-1] = yp[0]
    cases.append((1.0, scipy.splrep(xp, yp, per=1), 1, 1))
    for at, tck, per, m in cases:
        theirs, mine = scipy.insert(at, tck, m=m, per=per), ours.insert(at, tck, m=m, per=per)
        np.testing.assert_array_equal(mine[0], theirs[0])
        n = len(theirs[0]) - theirs[2] - 1
        for a, b in zip(np.atleast_2d(theirs[1]), np.atleast_2d(mine[1])):
            np.testing.assert_allclose(b[:n], a[:n], rtol=0, atol=1e-14)
        assert isinstance(mine, tuple) and mine[2] == theirs[2]
    spline = ours.make_interp_spline(x, np.sin(x))
    inserted = ours.insert(4.5, spline, m=2)
    assert isinstance(inserted, ours.BSpline)
    np.testing.assert_allclose(inserted(x), spline(x), rtol=0, atol=1e-14)


def test_the_legacy_fitpack_doors_treat_complex_data_as_scipy_does():
    """SciPy 1.17's splrep casts complex y to float with a ComplexWarning and fits the real
    part; its splprep refuses complex coordinates with TypeError. Ours do the same (issue 47
    said both raise; on this SciPy they do not)."""
    from splinegpu import interpolate as ours

    x = np.linspace(0, 1, 10)
    fits = []
    for module in (interpolate, ours):
        # numpy.exceptions from NumPy 1.25; numpy.ComplexWarning before it.
        with pytest.warns(getattr(np, "exceptions", np).ComplexWarning):
            fits.append(module.splrep(x, x + 1j * x))
        with pytest.raises(TypeError):
            module.splprep([x, x + 1j * x])
    (t_theirs, c_theirs, _), (t_ours, c_ours, _) = fits
    np.testing.assert_allclose(t_ours, t_theirs)
    np.testing.assert_allclose(c_ours[: len(c_theirs)], c_theirs, atol=1e-12)
