"""`splinegpu.interpolate.PPoly` and the splines' antiderivative, roots and solve against
SciPy's: evaluation, derivatives and antiderivatives of any degree, integrals, extend, and
roots with double roots, roots at knots, pieces equal to y everywhere, jumps across y and
extrapolation."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import splinegpu.interpolate as si

interpolate = pytest.importorskip("scipy.interpolate")


def close(got, want, what, tolerance=1e-10):
    assert np.shape(got) == np.shape(want), what
    finite = np.abs(np.asarray(want))[np.isfinite(want)]
    scale = max(finite.max() if finite.size else 1.0, 1e-300)
    np.testing.assert_allclose(got, want, rtol=0, atol=tolerance * scale, equal_nan=True,
                               err_msg=what)


def same_roots(got, want, x, what, within=1e-10):
    """The same count, each within `within` of the breakpoints' span (NaN where SciPy has
    NaN)."""
    assert len(got) == len(want), f"{what}: {got} vs {want}"
    close(np.asarray(got, float), np.asarray(want, float), what,
          tolerance=within * (x[-1] - x[0]) / max(np.abs(want[np.isfinite(want)]).max(
              initial=0.0), 1e-300))


@pytest.mark.parametrize("k", [1, 2, 4, 6])
@pytest.mark.parametrize("shape,axis", [((), 0), ((2, 3), 0), ((2, 3), 1)])
def test_ppoly_evaluates_differentiates_and_integrates_as_scipy(k, shape, axis):
    rng = np.random.default_rng(k + len(shape) + axis)
    x = np.concatenate([[0.0], np.cumsum(10 ** rng.uniform(-1, 1, 7))])
    # With axis a, k and m are c's axes a and a + 1 (SciPy's layout).
    c = rng.uniform(-1, 1, (*shape[:axis], k, 7, *shape[axis:]))
    q = np.concatenate([rng.uniform(x[0] - 1, x[-1] + 1, 50), x, [np.nan]])
    for extrapolate in (None, True, False, "periodic"):
        ours = si.PPoly(c, x, extrapolate=extrapolate, axis=axis)
        theirs = interpolate.PPoly(c, x, extrapolate=extrapolate, axis=axis)
        for nu in range(k + 1):
            close(ours(q, nu), theirs(q, nu), f"k={k} {extrapolate} nu={nu}")
            close(ours.derivative(nu)(q), theirs.derivative(nu)(q), f"derivative({nu})")
        for nu in (1, 2, 3):
            a, b = ours.antiderivative(nu), theirs.antiderivative(nu)
            assert a.extrapolate == b.extrapolate
            close(a.c, b.c, f"antiderivative({nu}).c")
            close(a(q), b(q), f"antiderivative({nu})")
        for lo, hi in [(x[1] + 0.1, x[5]), (x[-1], x[0] - 3), (x[0] - 20, x[-1] + 33)]:
            close(ours.integrate(lo, hi), theirs.integrate(lo, hi), f"integrate({lo}, {hi})",
                  tolerance=1e-9)


def test_extend_on_both_sides_is_scipys():
    rng = np.random.default_rng(2)
    c, x = rng.uniform(-1, 1, (4, 3)), np.array([0.0, 1.0, 2.0, 3.5])
    ours, theirs = si.PPoly(c, x), interpolate.PPoly(c, x)
    for more_c, more_x in [(rng.uniform(-1, 1, (2, 2)), [4.0, 5.0]),
                           (rng.uniform(-1, 1, (4, 1)), [-2.0])]:
        ours.extend(more_c, more_x)
        theirs.extend(more_c, more_x)
        close(ours.c, theirs.c, "c")
        np.testing.assert_array_equal(ours.x, theirs.x)
        q = np.linspace(-3, 6, 40)
        close(ours(q), theirs(q), "extended")
    with pytest.raises(ValueError, match="wholly to the right or to the left"):
        ours.extend(c[:, :1], [1.5])


def test_roots_and_solve_are_scipys_on_the_hard_cases():
    x = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    cases = {
        # (x - 0.5)^2 (x - 0.8) on [0, 1]: a double root; a root exactly at the knot 2.
        "double root": np.array([[1, 0, 1, 0], [-1.8, 0, 0, 0], [1.05, 0, -1, 1],
                                 [-0.2, 0, 0, 0]]),
        "zero piece": np.array([[0, 1, 0, 0], [0, -1, 0, 0], [0, 0, 0, 1], [0, 0, 0, -1]]),
        "jump across zero": np.array([[0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 1, 1],
                                      [-1, 1, -1, 0.5]]),
    }
    for name, c in cases.items():
        ours, theirs = si.PPoly(c, x), interpolate.PPoly(c, x)
        for discontinuity in (True, False):
            for extrapolate in (True, False):
                for y in (0.0, 0.5, -1.0):
                    # A double root moves by about sqrt(eps) under the last bit of its
                    # coefficients (SciPy's own roots there are that far from the exact
                    # 0.5): within 1e-7 of the span, the rest within 1e-10.
                    same_roots(ours.solve(y, discontinuity, extrapolate),
                               theirs.solve(y, discontinuity, extrapolate), x,
                               f"{name}, y={y}, {discontinuity}, {extrapolate}",
                               within=1e-7 if name == "double root" else 1e-10)


@pytest.mark.parametrize("seed", range(6))
def test_spline_roots_antiderivatives_and_solve_match_scipy(seed):
    rng = np.random.default_rng(seed)
    x = np.concatenate([[0.0], np.cumsum(10 ** rng.uniform(-2, 2, 20))])
    y = rng.uniform(-1, 1, (21, 2))
    pairs = [(si.CubicSpline(x, y), interpolate.CubicSpline(x, y)),
             (si.PchipInterpolator(x, y), interpolate.PchipInterpolator(x, y)),
             (si.Akima1DInterpolator(x, y[:, 0], method="makima"),
              interpolate.Akima1DInterpolator(x, y[:, 0], method="makima"))]
    for ours, theirs in pairs:
        for extrapolate in (None, True, False):
            got, want = ours.roots(extrapolate=extrapolate), theirs.roots(
                extrapolate=extrapolate)
            for g, w in zip(np.atleast_1d(got), np.atleast_1d(want)) if got.dtype == object \
                    else [(got, want)]:
                same_roots(g, w, x, f"{type(ours).__name__} roots, {extrapolate}")
        got, want = ours.solve(0.3), theirs.solve(0.3)
        for g, w in zip(np.atleast_1d(got), np.atleast_1d(want)) if got.dtype == object \
                else [(got, want)]:
            same_roots(g, w, x, f"{type(ours).__name__} solve(0.3)")
        q = rng.uniform(x[0] - 1, x[-1] + 1, 40)
        close(ours.antiderivative(2)(q), theirs.antiderivative(2)(q), "antiderivative(2)",
              tolerance=1e-9)


def test_ppoly_refuses_what_it_cannot_hold():
    with pytest.raises(ValueError, match="x: must be finite and strictly increasing or "
                       "decreasing"):
        si.PPoly(np.ones((4, 2)), [2.0, 3.0, 0.0])
    with pytest.raises(ValueError, match="c: 2 pieces for 4 breakpoints"):
        si.PPoly(np.ones((4, 2)), [0.0, 1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="only for real-valued"):
        si.PPoly(np.ones((4, 1)) * 1j, [0.0, 1.0]).roots()
    with pytest.raises(ValueError, match="nu: must be an integer >= 0"):
        si.PPoly(np.ones((4, 1)), [0.0, 1.0])(0.5, nu=-1)


def test_batched_roots_and_solve_equal_scipys_loop():
    rng = np.random.default_rng(17)
    xs = [np.cumsum(10 ** rng.uniform(-1, 1, n)) for n in rng.integers(2, 30, 40)]
    ys = [rng.uniform(-1, 1, len(x)) for x in xs]
    batches = [
        (si.CubicSplines(xs, [y[:, None] for y in ys], bc_type="natural"),
         lambda x, y: interpolate.CubicSpline(x, y, bc_type="natural")),
        (si.PchipInterpolators(xs, [y[:, None] for y in ys]), interpolate.PchipInterpolator),
        (si.Akima1DInterpolators(xs, [y[:, None] for y in ys], method="makima"),
         lambda x, y: interpolate.Akima1DInterpolator(x, y, method="makima")),
    ]
    for batch, scipy_class in batches:
        for y0, extrapolate in [(0.0, None), (0.25, True), (-0.5, False)]:
            roots, offsets = batch.solve(y0, extrapolate=extrapolate)
            for i, (x, y) in enumerate(zip(xs, ys)):
                same_roots(roots[offsets[i]:offsets[i + 1]],
                           scipy_class(x, y).solve(y0, extrapolate=extrapolate), x,
                           f"{type(batch).__name__} spline {i}, y={y0}, {extrapolate}")
    with pytest.raises(ValueError, match="solve: spline 0 has 2 values per x"):
        si.CubicSplines(xs, [np.stack([y, y], axis=1) for y in ys]).roots()


def test_a_batch_of_ppolys_is_scipys_one_by_one():
    rng = np.random.default_rng(31)
    xs = [np.cumsum(10 ** rng.uniform(-1, 1, n)) for n in rng.integers(2, 20, 30)]
    cs = [rng.uniform(-1, 1, (4, len(x) - 1, 2)) for x in xs]
    batch = si.PPolys(cs, xs)
    theirs = [interpolate.PPoly(c, x) for c, x in zip(cs, xs)]
    qs = [rng.uniform(x[0], x[-1], 15) for x in xs]
    for nu in range(3):
        values, offsets = batch(qs, nu)
        for i, (q, single) in enumerate(zip(qs, theirs)):
            np.testing.assert_allclose(values[offsets[i]:offsets[i + 1]], single(q, nu),
                                       rtol=1e-12, atol=1e-12)
    got = batch.integrate(-1.0, 50.0)
    for i, single in enumerate(theirs):
        np.testing.assert_allclose(got[i], single.integrate(-1.0, 50.0), rtol=1e-11)
    roots, offsets = si.PPolys([c[..., 0] for c in cs], xs).roots()
    for i, (c, x) in enumerate(zip(cs, xs)):
        want = interpolate.PPoly(c[..., 0], x).roots()
        np.testing.assert_allclose(roots[offsets[i]:offsets[i + 1]], want,
                                   atol=1e-10 * (x[-1] - x[0]))
    with pytest.raises(ValueError, match=r"xs\[1\]: must be"):
        si.PPolys(cs[:2], [xs[0], xs[1][::-1]])
    with pytest.raises(ValueError, match=r"cs\[0\]: must have the shape"):
        si.PPolys([np.ones((5, 3))], [np.arange(4.0)])


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(5, 19), st.booleans())
def test_roots_of_high_degree_pieces_are_scipys(seed, degree, extrapolate):
    """Pieces of degree 5 to 19, the end pieces extrapolated or not: SciPy's roots, the same
    count, within 1e-8 of the span (SciPy's own test_roots_random's tolerance)."""
    rng = np.random.default_rng(seed)
    c = rng.uniform(-1, 1, (degree + 1, 6))
    x = np.sort(rng.uniform(0, 10, 7))
    ours = si.PPoly(c, x).roots(extrapolate=extrapolate)
    theirs = interpolate.PPoly(c, x).roots(extrapolate=extrapolate)
    assert len(ours) == len(theirs)
    np.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-8 * 10)


def test_a_tiny_piece_keeps_its_terms_for_the_roots():
    # x^3 - 1 given on [0, 1e-5]: SciPy finds the extrapolated root at 1.
    for module in (si, interpolate):
        np.testing.assert_allclose(module.PPoly([[1], [0], [0], [-1]], [0, 1e-5]).roots(), [1.0])


def test_descending_breakpoints_are_scipys():
    rng = np.random.default_rng(2)
    c, x = rng.uniform(-2, 2, (4, 5)), np.sort(rng.uniform(0, 10, 6))[::-1]
    ours, theirs = si.PPoly(c, x), interpolate.PPoly(c, x)
    q = rng.uniform(-3, 13, 40)
    for nu in range(3):
        np.testing.assert_allclose(ours(q, nu), theirs(q, nu), rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(ours.integrate(-1, 12), theirs.integrate(-1, 12), rtol=1e-13)
    np.testing.assert_allclose(np.sort(ours.roots()), np.sort(theirs.roots()), rtol=1e-12)


def test_a_splines_derivatives_are_splines_and_minus_one_integrates():
    x = np.linspace(0, 6, 13)
    ours, theirs = si.CubicSpline(x, np.sin(x)), interpolate.CubicSpline(x, np.sin(x))
    d = ours.derivative()
    assert isinstance(d, si.PPoly) and isinstance(d, si.CubicSpline)
    np.testing.assert_allclose(d.roots(), theirs.derivative().roots(), rtol=0, atol=1e-12)
    q = np.linspace(-1, 7, 17)
    np.testing.assert_allclose(ours.derivative(-1)(q), theirs.antiderivative()(q), rtol=0,
                               atol=1e-12)
    np.testing.assert_allclose(ours.antiderivative(2)(q), theirs.antiderivative(2)(q), rtol=0,
                               atol=1e-12)


def test_misaligned_arrays_are_read_right():
    """Arrays as Dask hands them over from a network buffer (misaligned): breakpoints,
    coefficients and points, through every native door of PPoly and the splines."""

    def misaligned(a):
        raw = bytearray(a.nbytes + 1)
        out = np.frombuffer(raw, dtype=np.float64, count=a.size, offset=1).reshape(a.shape)
        out[...] = a
        assert not out.flags.aligned
        return out

    rng = np.random.default_rng(6)
    c, x = rng.uniform(-1, 1, (5, 6)), np.sort(rng.uniform(0, 10, 7))
    q = rng.uniform(-2, 12, 9)
    ours = si.PPoly(misaligned(c), misaligned(x))
    theirs = interpolate.PPoly(c, x)
    np.testing.assert_allclose(ours(misaligned(q)), theirs(q), rtol=1e-13)
    np.testing.assert_allclose(ours.integrate(-1, 11), theirs.integrate(-1, 11), rtol=1e-13)
    np.testing.assert_allclose(ours.antiderivative()(q), theirs.antiderivative()(q),
                               rtol=1e-12)
    spline = si.make_interp_spline(misaligned(x), misaligned(x ** 2), k=4)
    np.testing.assert_allclose(spline(q), interpolate.make_interp_spline(x, x ** 2, k=4)(q),
                               rtol=1e-10)


@pytest.mark.parametrize("descending", [False, True])
def test_bpoly_answers_as_scipys(descending):
    """BPoly against SciPy's: calls (derivatives 0 to past the degree, every extrapolate
    mode), antiderivatives, integrals (periodic too), extend, and complex coefficients."""
    rng = np.random.default_rng(31)
    x = np.sort(rng.uniform(0, 5, 9))
    if descending:
        x = x[::-1].copy()
    c = rng.normal(size=(6, 8, 2))
    ours, theirs = si.BPoly(c, x), interpolate.BPoly(c, x)
    xi = np.linspace(-1, 6, 41)
    for nu in range(7):
        np.testing.assert_allclose(ours(xi, nu), theirs(xi, nu), rtol=1e-12, atol=1e-9)
    for mode in (True, False, "periodic"):
        np.testing.assert_allclose(ours(xi, 1, extrapolate=mode), theirs(xi, 1, extrapolate=mode),
                                   rtol=1e-12, atol=1e-9)
        for a, b in ((0.3, 4.1), (-3.0, 11.5), (4.0, 0.5)):
            np.testing.assert_allclose(ours.integrate(a, b, extrapolate=mode),
                                       theirs.integrate(a, b, extrapolate=mode), rtol=1e-10,
                                       atol=1e-9)
    for nu in (1, 2, 3):
        # Degree 8 extrapolated to s = 22 on the narrowest end piece is ill-conditioned: both
        # evaluations are within 2e-8 of the exact value there (ours 2e-9, from fractions).
        np.testing.assert_allclose(ours.antiderivative(nu)(xi), theirs.antiderivative(nu)(xi),
                                   rtol=1e-7, atol=1e-9)
    complex_c = c[..., 0] * (1 + 0.5j)
    np.testing.assert_allclose(si.BPoly(complex_c, x)(xi, 2),
                               interpolate.BPoly(complex_c, x)(xi, 2), rtol=1e-12, atol=1e-9)
    if not descending:
        more = rng.normal(size=(3, 2, 2))
        ours.extend(more, [6.0, 7.0])
        theirs.extend(more, [6.0, 7.0])
        np.testing.assert_allclose(ours(np.linspace(0, 7, 30)), theirs(np.linspace(0, 7, 30)),
                                   rtol=1e-12, atol=1e-9)


def test_bpoly_from_derivatives_meets_them_and_converts_both_ways():
    """from_derivatives' pieces take the given derivatives at the breakpoints (their own
    check, then SciPy's coefficients); power and Bernstein bases convert into each other, ours
    and SciPy's classes alike; a polynomial of the wrong basis is a TypeError."""
    rng = np.random.default_rng(5)
    xi = np.array([0.0, 0.7, 2.0, 2.5])
    yi = [rng.normal(size=n) for n in (3, 2, 4, 1)]
    ours = si.BPoly.from_derivatives(xi, yi)
    for i, y in enumerate(yi):
        at = np.array([xi[i]])
        for q, v in enumerate(y):
            # Piece i holds xi[i] (the last piece the last point): its q-th derivative there.
            assert abs(ours(at, q)[0] - v) < 1e-9 * (1 + abs(v)), (i, q)
    np.testing.assert_allclose(ours.c, interpolate.BPoly.from_derivatives(xi, yi).c, rtol=1e-12,
                               atol=1e-12)
    even = [rng.normal(size=2) for _ in xi]
    np.testing.assert_allclose(si.BPoly.from_derivatives(xi, even, orders=3).c,
                               interpolate.BPoly.from_derivatives(xi, even, orders=3).c,
                               rtol=1e-12, atol=1e-12)
    # An order the ends' counts cannot give: SciPy's ValueError, its words.
    for module in (si, interpolate):
        with pytest.raises(ValueError, match=r"Point 2\.0 has 4 derivatives, point 2\.5 has 1"):
            module.BPoly.from_derivatives(xi, yi, orders=3)
    pp = si.PPoly(rng.normal(size=(4, 3)), [0.0, 1.0, 1.5, 3.0])
    for poly in (si.BPoly.from_power_basis(pp), interpolate.BPoly.from_power_basis(
            interpolate.PPoly(pp.c, pp.x))):
        back = si.PPoly.from_bernstein_basis(poly)
        np.testing.assert_allclose(back.c, pp.c, rtol=1e-12, atol=1e-12)
    with pytest.raises(TypeError, match="from_power_basis only accepts PPoly"):
        si.BPoly.from_power_basis(si.BPoly(pp.c, pp.x))
    with pytest.raises(TypeError, match="from_bernstein_basis only accepts BPoly"):
        si.PPoly.from_bernstein_basis(pp)
