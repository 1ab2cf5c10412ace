"""`BSpline` and `make_interp_spline` against SciPy's: knots and coefficients (exactly the
same knots, coefficients within 1e-12 of the largest), values and derivatives at any x in
every extrapolate mode, `derivative`/`antiderivative` (SciPy's t, c and k), `integrate`, for
degrees 0 to 5, repeated and unclamped knots, 1-D/N-D/complex c, every axis, uneven x to 1e6;
where SciPy is the less accurate side (a degree-5 antiderivative far outside its knots), an
exact rational de Boor evaluation decides."""

import copy
import pickle
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import splinegpu.interpolate as si

interpolate = pytest.importorskip("scipy.interpolate")


def assert_close(got, want, what, tolerance=1e-12):
    got, want = np.asarray(got), np.asarray(want)
    assert got.shape == want.shape, what
    scale = np.nanmax(np.abs(want)) if np.isfinite(want).any() else 1.0
    np.testing.assert_allclose(got, want, rtol=0, atol=tolerance * max(scale, 1e-300),
                               equal_nan=True, err_msg=what)


def uneven(n, ratio, rng):
    h = ratio ** rng.uniform(-0.5, 0.5, n - 1)
    return np.concatenate([[0.0], np.cumsum(h)])


def queries(lo, hi, rng):
    span = hi - lo
    return np.concatenate([rng.uniform(lo, hi, 50), [lo, hi, lo - 1e-14 * span, np.nan],
                           rng.uniform(lo - span / 4, hi + span / 4, 20)])


BCS = [None, "not-a-knot", "natural", "clamped", "periodic", (None, None),
       ("natural", "clamped"), ([(1, 0.5)], [(2, -1.0)]), ([(2, 3.0)], "natural")]


@pytest.mark.parametrize("bc_type", BCS)
@pytest.mark.parametrize("shape,axis", [((), 0), ((3,), 0), ((2, 3), -1)])
@pytest.mark.parametrize("ratio", [1.0, 1e3, 1e6])
def test_make_interp_spline_is_scipys(bc_type, shape, axis, ratio):
    rng = np.random.default_rng(len(shape) + int(np.log10(ratio)))
    x = uneven(12, ratio, rng)
    y = rng.uniform(-2, 2, (len(x), *shape))
    if bc_type == "periodic":
        y[-1] = y[0]
    y = np.moveaxis(y, 0, axis)
    if isinstance(bc_type, tuple):
        # SciPy's explicit ends take values of y's other axes' shape (ours broadcast).
        bc_type = tuple(end if not isinstance(end, list) else
                        [(order, np.full(shape, value)) for order, value in end]
                        for end in bc_type)
    ours = si.make_interp_spline(x, y, bc_type=bc_type, axis=axis)
    theirs = interpolate.make_interp_spline(x, y, bc_type=bc_type, axis=axis)
    np.testing.assert_array_equal(ours.t, theirs.t)
    assert (ours.k, ours.axis, ours.extrapolate) == (theirs.k, theirs.axis, theirs.extrapolate)
    # SciPy's own coefficients carry its banded solve's rounding, which grows with the ratio.
    assert_close(ours.c, theirs.c, "c", tolerance=1e-12 * max(ratio, 1.0) ** 0.5)
    q = queries(x[0], x[-1], rng)
    for nu in range(5):
        for extrapolate in (None, True, False, "periodic"):
            assert_close(ours(q, nu, extrapolate), theirs(q, nu, extrapolate),
                         f"nu={nu}, extrapolate={extrapolate}", tolerance=1e-10)


def test_complex_y_and_the_ends_one_by_one():
    rng = np.random.default_rng(4)
    x = uneven(9, 10.0, rng)
    y = rng.uniform(-1, 1, (9, 2)) + 1j * rng.uniform(-1, 1, (9, 2))
    for bc in (None, "natural", ([(1, [1j, 2.0])], [(1, [0.0, -1.0])])):
        ours = si.make_interp_spline(x, y, bc_type=bc)
        theirs = interpolate.make_interp_spline(x, y, bc_type=bc)
        assert_close(ours.c, theirs.c, f"c, {bc}")
        q = queries(x[0], x[-1], rng)
        assert_close(ours(q, 1), theirs(q, 1), f"values, {bc}", tolerance=1e-10)


def random_bspline(k, rng, repeat=True, clamped=False):
    """Knots with interior repeats (up to k times) or unclamped ends, and coefficients."""
    interior = np.sort(rng.uniform(0, 10, 8))
    if repeat and k > 0:
        interior = np.sort(np.concatenate([interior, np.repeat(interior[3], k - 1)]))
    if clamped:
        t = np.concatenate([np.zeros(k + 1) - 1, interior, np.full(k + 1, 11.0)])
    else:
        t = np.concatenate([np.sort(rng.uniform(-3, 0, k + 1)), interior,
                            np.sort(rng.uniform(10, 13, k + 1))])
    n = len(t) - k - 1
    return t, rng.uniform(-2, 2, (n + 2, 2))  # two rows past n, kept and ignored


@pytest.mark.parametrize("k", [0, 1, 2, 3, 4, 5])
@pytest.mark.parametrize("clamped", [False, True])
def test_bspline_is_scipys_for_every_degree(k, clamped):
    rng = np.random.default_rng(10 * k + clamped)
    t, c = random_bspline(k, rng, clamped=clamped)
    for extrapolate in (True, False, "periodic"):
        ours = si.BSpline(t, c, k, extrapolate=extrapolate)
        theirs = interpolate.BSpline(t, c, k, extrapolate=extrapolate)
        q = queries(t[k], t[len(t) - k - 1], rng)
        for nu in range(k + 2):
            assert_close(ours(q, nu), theirs(q, nu), f"k={k}, {extrapolate}, nu={nu}",
                         tolerance=1e-11)
        # Column by column, without the rows past n: SciPy's integrate fails on an N-D c of
        # degree 0 and on rows past len(t) - 1, and past the base interval its N-D path gives
        # NaN where its 1-D path (and ours) give 0.
        n = len(t) - k - 1
        columns = [interpolate.BSpline(t, c[:n, j], k, extrapolate=extrapolate) for j in (0, 1)]
        for a, b in ((1.0, 9.0), (-5.0, 14.0), (9.5, -2.0), (11.0, 12.0)):
            assert_close(ours.integrate(a, b), [s.integrate(a, b) for s in columns],
                         f"k={k}, {extrapolate}, integrate({a}, {b})", tolerance=1e-11)


@pytest.mark.parametrize("k", [1, 2, 3])
def test_derivatives_and_antiderivatives_are_scipys_splines(k):
    rng = np.random.default_rng(k)
    t, c = random_bspline(k, rng, repeat=False)
    c = c[:, 0] + 1j * c[:, 1]
    ours, theirs = si.BSpline(t, c, k), interpolate.BSpline(t, c, k)
    for nu in range(1, k + 1):
        for a, b in ((ours.derivative(nu), theirs.derivative(nu)),
                     (ours.antiderivative(nu), theirs.antiderivative(nu))):
            np.testing.assert_array_equal(a.t, b.t)
            assert a.k == b.k
            assert_close(a.c, b.c, f"c, nu={nu}")
            q = queries(t[k], t[-k - 1], rng)
            inside = (q >= t[a.k]) & (q <= t[len(t) - k - 1])
            assert_close(a(q[inside]), b(q[inside]), f"values, nu={nu}", tolerance=1e-11)
    periodic = si.BSpline(t, c, k, extrapolate="periodic")
    assert periodic.antiderivative().extrapolate is False
    assert periodic.derivative().extrapolate == "periodic"


def exact_value(spline, x: float) -> float:
    """An independent check: de Boor's algorithm in exact rationals on the last interval
    (the polynomial there continues past the knots)."""
    t = [Fraction(v) for v in spline.t]
    c = [Fraction(v) for v in spline.c]
    k = spline.k
    j = len(t) - k - 2
    while t[j] == t[j + 1]:
        j -= 1
    d = [c[j - k + s] for s in range(k + 1)]
    for r in range(1, k + 1):
        for s in range(k, r - 1, -1):
            i = j - k + s
            w = (Fraction(x) - t[i]) / (t[i + k + 1 - r] - t[i])
            d[s] = (1 - w) * d[s - 1] + w * d[s]
    return float(d[k])


def test_a_degree_5_antiderivative_far_past_its_knots_against_exact_arithmetic():
    rng = np.random.default_rng(1)
    x = np.sort(rng.uniform(0, 10, 12))
    spline = si.make_interp_spline(x, rng.normal(size=12), bc_type="natural")
    ours = spline.antiderivative(2)
    theirs = interpolate.BSpline(spline.t, spline.c, 3).antiderivative(2)
    for q in (x[-1] + 2.0, x[-1] + 5.0):
        exact = exact_value(ours, q)
        assert abs(ours(q) - exact) <= 1e-9 * abs(exact)
        # SciPy's error here, for the record (it exceeds ours; the test does not depend on it).
        print(f"x={q}: ours {abs(ours(q) - exact) / abs(exact):.1e}, SciPy's "
              f"{abs(theirs(q) - exact) / abs(exact):.1e}")


def test_the_gpu_keeps_the_promise(gpu):
    rng = np.random.default_rng(7)
    x = uneven(20, 1e3, rng)
    y = rng.uniform(-2, 2, (20, 3))
    ours = si.make_interp_spline(x, y, context=gpu)
    general = si.BSpline(ours.t, ours.c, 3, context=gpu)
    theirs = interpolate.make_interp_spline(x, y)
    q = queries(x[0], x[-1], rng)
    for nu in range(3):
        for spline in (ours, general):
            got = spline(q, nu)
            assert got.dtype == np.float32
            assert_close(got, theirs(q, nu), f"GPU nu={nu}", tolerance=2e-5)


def test_bsplines_pickle_copy_and_keep_their_arrays():
    rng = np.random.default_rng(3)
    x = uneven(10, 10.0, rng)
    y = rng.uniform(-1, 1, (10, 2))
    for spline in (si.make_interp_spline(x, y, bc_type="clamped"),
                   si.BSpline(*random_bspline(4, rng))):
        q = queries(x[0], x[-1], rng)
        for again in (pickle.loads(pickle.dumps(spline)), copy.deepcopy(spline)):
            np.testing.assert_array_equal(again.t, spline.t)
            np.testing.assert_array_equal(again(q, 1), spline(q, 1))
            with pytest.raises(ValueError, match="read-only"):
                again.c[0] = 1.0
        with pytest.raises(ValueError, match="read-only"):
            spline.t[0] = 1.0
    t, c = random_bspline(3, rng)
    spline = si.BSpline(t, c, 3)
    t[5] += 1.0
    c[0] = 99.0
    assert spline.t[5] != t[5] and spline.c[0, 0] != 99.0


def test_bad_input_is_named():
    t, c = random_bspline(3, np.random.default_rng(0))
    x = np.linspace(0.0, 1.0, 8)
    cases = [
        (lambda: si.BSpline(t[::-1], c, 3), "t: the knots must be in non-decreasing order"),
        (lambda: si.BSpline(t[:7], c, 3), "t: need at least 8 knots for degree 3"),
        (lambda: si.BSpline(np.where(t > 5, np.nan, t), c, 3), "t: the knots must be finite"),
        (lambda: si.BSpline(t, c[:5], 3), "c: 5 coefficients for 18 knots"),
        (lambda: si.BSpline(t, c, -1), "k: must be an integer >= 0"),
        (lambda: si.BSpline(t, c, 3, axis=2), "axis: must be an integer from -2 to 1"),
        (lambda: si.BSpline(np.zeros(8), c, 3), r"t: the base interval \[t\[3\], t\[4\]\]"),
        (lambda: si.BSpline(t, c, 3)(0.0, nu=-1), "nu: must be an integer >= 0"),
        (lambda: si.BSpline(t, c, 3).derivative(4), "nu: a spline of degree 3 has"),
        (lambda: si.BSpline(np.r_[0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2], np.ones(8), 3
                            ).derivative(), "internal repeated knots"),
        # make_interp_spline's are SciPy's own words.
        (lambda: si.make_interp_spline(t, t), "Expect x to not have duplicates"),
        (lambda: si.make_interp_spline(x, x[1:]), "Shapes of x"),
        (lambda: si.make_interp_spline([0, 1, 2], [0, 1, 0]),
         "The number of derivatives at boundaries does not match: expected 1, got 0"),
        (lambda: si.make_interp_spline(x, x, bc_type=([(1, 0)], None)),
         "The number of derivatives at boundaries does not match: expected 2, got 1"),
        (lambda: si.make_interp_spline(x, x, bc_type=([(4, 0)], [(1, 0)])),
         "Bad boundary conditions at"),
        (lambda: si.make_interp_spline(x, x, bc_type="flat"),
         "Unknown boundary condition : flat"),
        (lambda: si.make_interp_spline(x, x, k=1, bc_type="natural"),
         "Too much info for k=1"),
        (lambda: si.make_interp_spline(x, x, t=t[:6]), "Got 6 knots, need at least"),
    ]
    for make, message in cases:
        with pytest.raises(ValueError, match=message):
            make()


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(0, 5), st.sampled_from([True, False, "periodic"]))
def test_random_bsplines_are_scipys(seed, k, extrapolate):
    rng = np.random.default_rng(seed)
    t, c = random_bspline(k, rng, repeat=bool(rng.integers(2)), clamped=bool(rng.integers(2)))
    ours = si.BSpline(t, c[:, 0], k, extrapolate=extrapolate)
    theirs = interpolate.BSpline(t, c[:, 0], k, extrapolate=extrapolate)
    q = queries(t[k], t[len(t) - k - 1], rng)
    nu = int(rng.integers(0, k + 1))
    assert_close(ours(q, nu), theirs(q, nu), f"nu={nu}", tolerance=1e-11)


@pytest.mark.parametrize("bc_type", [None, "natural", "periodic", ([(1, 0.5)], [(2, -1.0)])])
def test_make_interp_splines_are_scipys_one_by_one(bc_type):
    rng = np.random.default_rng(8)
    xs = [uneven(int(n), 1e3, rng) for n in rng.integers(4, 30, 40)]
    ys = [rng.uniform(-1, 1, len(x)) for x in xs]
    if bc_type == "periodic":
        for y in ys:
            y[-1] = y[0]
    batch = si.make_interp_splines(xs, ys, bc_type=bc_type)
    singles = [interpolate.make_interp_spline(x, y, bc_type=bc_type) for x, y in zip(xs, ys)]
    qs = [rng.uniform(x[0], x[-1], 25) for x in xs]
    for nu in range(3):
        values, offsets = batch(qs, nu)
        for i, (q, theirs) in enumerate(zip(qs, singles)):
            assert_close(values[offsets[i]:offsets[i + 1], 0], theirs(q, nu), f"{i}, nu={nu}",
                         tolerance=1e-10)
    for i in (0, 17, 39):
        np.testing.assert_array_equal(batch[i].t, singles[i].t)
        assert_close(batch[i].c, singles[i].c, f"c of spline {i}")
        assert batch[i].extrapolate == singles[i].extrapolate
    roots, offsets = batch.roots()
    for i in range(len(xs)):
        # SciPy's BSpline has no roots: its PPoly's (the same pieces on every x).
        want = interpolate.PPoly.from_spline(singles[i]).roots()
        want = want[(want >= xs[i][0]) & (want <= xs[i][-1])]
        got = roots[offsets[i]:offsets[i + 1]]
        got = got[(got >= xs[i][0]) & (got <= xs[i][-1])]
        assert_close(got, want, f"roots of spline {i}", tolerance=1e-10)
    lo = np.array([x[0] - 1 for x in xs])
    hi = np.array([x[-1] * 0.7 for x in xs])
    got = batch.integrate(lo, hi)
    for i, theirs in enumerate(singles):
        assert_close(got[i, 0], theirs.integrate(lo[i], hi[i]), f"integral {i}")


def test_bsplines_are_scipys_one_by_one_and_travel():
    rng = np.random.default_rng(9)
    made = [random_bspline(3, rng, repeat=bool(i % 2), clamped=bool(i % 3)) for i in range(30)]
    ts = [t for t, _ in made]
    cs = [c for _, c in made]
    batch = si.BSplines(ts, cs, extrapolate=False)
    singles = [interpolate.BSpline(t, c, 3, extrapolate=False) for t, c in made]
    qs = [rng.uniform(t[3], t[len(t) - 4], 20) for t in ts]
    for nu in range(3):
        values, offsets = batch(qs, nu)
        for i, (q, theirs) in enumerate(zip(qs, singles)):
            assert_close(values[offsets[i]:offsets[i + 1]], theirs(q, nu), f"{i}, nu={nu}",
                         tolerance=1e-11)
    # extrapolate=False: zero outside the base interval, as BSpline's (SciPy's 1-D path).
    got = batch.integrate(-5.0, 20.0)
    for i, (t, c) in enumerate(made):
        n = len(t) - 4
        want = [interpolate.BSpline(t, c[:n, j], 3, extrapolate=False).integrate(-5.0, 20.0)
                for j in (0, 1)]
        assert_close(got[i], want, f"integral {i}")
    again = pickle.loads(pickle.dumps(batch))
    np.testing.assert_array_equal(again(qs)[0], batch(qs)[0])
    np.testing.assert_array_equal(again.integrate(-5.0, 20.0), got)
    np.testing.assert_array_equal(batch[7].t, ts[7])
    assert_close(batch[7](qs[7]), singles[7](qs[7]), "batch[7]")
    bad = [*ts[:4], ts[4][::-1]]
    with pytest.raises(ValueError, match=r"ts\[4\]: the knots must be in non-decreasing"):
        si.BSplines(bad, cs[:5])
    with pytest.raises(ValueError, match=r"cs\[2\]: 3 coefficients"):
        si.BSplines(ts[:3], [*cs[:2], cs[2][:3]])
    with pytest.raises(ValueError, match=r"cs\[1\]: the coefficients must be finite"):
        si.BSplines(ts[:2], [cs[0], cs[1] * np.nan])
    empty = si.BSplines([], [])
    assert len(empty) == 0 and len(empty.roots()[0]) == 0
    with pytest.raises(ValueError, match="k: a batch evaluates degrees up to 3"):
        si.BSplines(ts, cs, k=4)
    with pytest.raises(ValueError, match=r"xs\[1\]: not-a-knot needs at least 4 points"):
        si.make_interp_splines([np.arange(5.0), np.arange(3.0)], [np.ones(5), np.ones(3)])


def test_a_batch_with_a_broken_spline_takes_the_numpy_pieces():
    # A knot 4 times inside the base interval breaks the spline there: the crate's cubic
    # B-splines refuse it, SciPy takes it, and so does the batch (its pieces from NumPy).
    rng = np.random.default_rng(12)
    t = np.r_[0, 0, 0, 0, 1, 2, 2, 2, 2, 3, 4, 4, 4, 4.0]
    c = rng.uniform(-1, 1, (len(t) - 4, 2))
    batch = si.BSplines([t, t], [c, 2 * c])
    q = np.linspace(0, 4, 41)
    values, offsets = batch([q, q])
    theirs = interpolate.BSpline(t, c, 3)
    assert_close(values[offsets[0]:offsets[1]], theirs(q), "spline 0")
    assert_close(values[offsets[1]:offsets[2]], 2 * theirs(q), "spline 1")
