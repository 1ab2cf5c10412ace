"""splinegpu.CubicSpline against scipy.interpolate.CubicSpline: every bc_type, 1-D and N-D y,
uneven knots (spacing ratios to 1e6), nu = 0, 1, 2. The CPU backend within 1e-12 relative
(max |ours - SciPy| / max |SciPy| for each nu); the GPU backend (lavapipe in CI) within the
crate's stated f32 promise, computed per sample from the segment's coefficients.

One exception, measured: with spacing ratios of 1e6 the second derivative is as ill-conditioned
as the knots are uneven, and SciPy's own nu = 2 is off by ~1e-11 of its largest value (against
the same natural spline solved in 80-bit long double: SciPy 9.2e-12, ours 3.9e-12). There the
bound for nu = 2 is 2e-11."""

import numpy as np
import pytest
from scipy.interpolate import CubicSpline as SciPySpline

import splinegpu

# "derivatives": first derivatives 0.5 at the start and -2 at the end, ((1, v0), (1, vn)).
BC_TYPES = ["not-a-knot", "natural", "clamped", "periodic", "derivatives"]


def bc_of(bc, shape):
    if bc == "derivatives":
        return ((1, np.full(shape, 0.5)), (1, np.full(shape, -2.0)))
    return bc


def knots(kind, n, rng):
    if kind == "uneven":
        # Spacings spanning six decades, shuffled: neighbouring ratios up to 1e6.
        h = 10.0 ** rng.uniform(-3, 3, n - 1)
        h[0], h[1] = 1e-3, 1e3
        rng.shuffle(h)
        return np.concatenate([[0.0], np.cumsum(h)])
    return np.sort(rng.uniform(-5, 5, n))


def data(bc, n, shape, rng, x_kind):
    x = knots(x_kind, n, rng)
    y = rng.uniform(-2, 2, (n, *shape))
    if bc == "periodic":
        y[-1] = y[0]
    return x, y


def query(x, rng):
    q = np.concatenate([x, rng.uniform(x[0], x[-1], 500)])
    # Points inside the shortest and longest intervals too.
    i = np.argmin(np.diff(x))
    q = np.concatenate([q, x[i] + np.diff(x)[i] * rng.uniform(0, 1, 20)])
    return q


@pytest.mark.parametrize("bc", BC_TYPES, ids=str)
@pytest.mark.parametrize("shape", [(), (3,), (2, 2)], ids=str)
@pytest.mark.parametrize("x_kind", ["random", "uneven"])
def test_cpu_matches_scipy(bc, shape, x_kind):
    rng = np.random.default_rng(BC_TYPES.index(bc) * 100 + len(shape) * 10 + len(x_kind))
    x, y = data(bc, 12, shape, rng, x_kind)
    ours = splinegpu.CubicSpline(x, y, bc_type=bc_of(bc, shape))
    theirs = SciPySpline(x, y, bc_type=bc_of(bc, shape))
    q = query(x, rng)
    for nu in (0, 1, 2):
        a, b = ours(q, nu), theirs(q, nu)
        assert a.shape == b.shape
        err = np.max(np.abs(a - b)) / np.max(np.abs(b))
        assert err <= (2e-11 if nu == 2 and x_kind == "uneven" else 1e-12), (nu, err)
    # Each coefficient by what it contributes on its interval, c[k, j] h_j^(3-k): a cubic
    # coefficient of a 1e-3 interval is ill-determined by itself but contributes nothing.
    h = np.diff(x).reshape((1, -1) + (1,) * len(shape)) ** np.arange(3, -1, -1).reshape(
        (4, 1) + (1,) * len(shape))
    scaled_ours, scaled_theirs = ours.c * h, theirs.c * h
    assert ours.c.shape == theirs.c.shape
    np.testing.assert_allclose(scaled_ours, scaled_theirs, rtol=0,
                               atol=1e-12 * np.abs(scaled_theirs).max())
    np.testing.assert_array_equal(ours.x, theirs.x)
    d = ours.derivative(1)
    np.testing.assert_allclose(d(q), theirs.derivative(1)(q), rtol=0,
                               atol=1e-12 * np.abs(theirs(q, 1)).max())


@pytest.mark.parametrize("n", [2, 3])
@pytest.mark.parametrize("shape", [(), (3,)], ids=str)
@pytest.mark.parametrize("x_kind", ["random", "uneven"])
def test_not_a_knot_on_two_or_three_points_is_scipys_line_or_parabola(n, shape, x_kind):
    rng = np.random.default_rng(n * 10 + len(shape) + len(x_kind))
    x = knots(x_kind, n, rng) if x_kind == "random" else np.array([0.0, 1e-3, 1e3][:n])
    y = rng.uniform(-2, 2, (n, *shape))
    ours, theirs = splinegpu.CubicSpline(x, y), SciPySpline(x, y)
    q = np.concatenate([x, rng.uniform(x[0], x[-1], 200)])
    for nu in (0, 1, 2):
        a, b = ours(q, nu), theirs(q, nu)
        assert a.shape == b.shape
        scale = max(np.max(np.abs(b)), 1.0)
        atol = 1e-12 * scale
        if nu == 2:
            # A cubic held in its interval's local u rounds its second derivative by about
            # eps |y| / h^2: 4.4e-10 on the 1e-3 interval here (measured: 1.8e-9 on the line;
            # against the parabola computed exactly in fractions, ours 4.8e-10 of its scale off
            # and SciPy's own 1.0e-9).
            atol = max(atol, 50 * np.finfo(float).eps * np.max(np.abs(y)) / np.min(np.diff(x)) ** 2)
        np.testing.assert_allclose(a, b, rtol=0, atol=atol, err_msg=f"nu={nu}")
    # In a batch, beside a spline of 5 points: the same splines.
    x5 = np.sort(rng.uniform(-5, 5, 5))
    y5 = rng.uniform(-2, 2, (5, *shape))
    batch = splinegpu.CubicSplines([x, x5], [y.reshape(n, -1), y5.reshape(5, -1)])
    values, offsets = batch([q, x5])
    np.testing.assert_array_equal(values[offsets[0]:offsets[1]], ours(q).reshape(len(q), -1))


@pytest.mark.parametrize("bc", BC_TYPES, ids=str)
@pytest.mark.parametrize("shape", [(), (3,)], ids=str)
def test_complex_y_matches_scipy(bc, shape):
    rng = np.random.default_rng(BC_TYPES.index(bc) * 10 + len(shape))
    x, re = data(bc, 9, shape, rng, "random")
    _, im = data(bc, 9, shape, rng, "random")
    y = re + 1j * im
    if bc == "derivatives":
        bc_type = ((1, np.full(shape, 0.5 - 1j)), (1, np.full(shape, 2j)))
    else:
        bc_type = bc
    ours, theirs = splinegpu.CubicSpline(x, y, bc_type=bc_type), SciPySpline(x, y, bc_type=bc_type)
    q = query(x, rng)
    for nu in (0, 1, 2):
        a, b = ours(q, nu), theirs(q, nu)
        assert a.dtype == np.complex128 and a.shape == b.shape
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * np.abs(b).max(), err_msg=f"nu={nu}")
    h = np.diff(x).reshape((1, -1) + (1,) * len(shape)) ** np.arange(3, -1, -1).reshape(
        (4, 1) + (1,) * len(shape))
    np.testing.assert_allclose(ours.c * h, theirs.c * h, rtol=0,
                               atol=1e-12 * np.abs(theirs.c * h).max())
    np.testing.assert_allclose(ours.derivative(1)(q), theirs.derivative(1)(q), rtol=0,
                               atol=1e-12 * np.abs(theirs(q, 1)).max())


def test_axis_moves_like_scipy():
    rng = np.random.default_rng(5)
    x = np.sort(rng.uniform(0, 10, 9))
    y = rng.uniform(-1, 1, (4, 9, 2))
    q = rng.uniform(x[0], x[-1], (3, 5))
    ours, theirs = splinegpu.CubicSpline(x, y, axis=1), SciPySpline(x, y, axis=1)
    a, b = ours(q), theirs(q)
    assert a.shape == b.shape
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * np.abs(b).max())


def promise(spline_c, x, q, nu, extent):
    """The crate's f32 bound per query point (README "Accuracy"), from SciPy-form coefficients."""
    j = np.clip(np.searchsorted(x, q, side="right") - 1, 0, len(x) - 2)
    dt = np.diff(x)[j]
    c = spline_c[:, j].reshape(4, len(q), -1)
    a, b, cc, d = (np.abs(c[0]) * dt[:, None] ** 3, np.abs(c[1]) * dt[:, None] ** 2,
                   np.abs(c[2]) * dt[:, None], c[3])
    ulp = lambda v: np.spacing(np.abs(v).astype(np.float32)).astype(np.float64)  # noqa: E731
    if nu == 0:
        return 1e-5 * np.maximum(extent, a + b + cc) + 4 * ulp(np.abs(d) + a + b + cc) + ulp(d)
    if nu == 1:
        return 1e-4 * (3 * a + 2 * b + cc) / dt[:, None] + 2 * ulp(cc / dt[:, None])
    return 1e-4 * (6 * a + 2 * b) / dt[:, None] ** 2 + 2 * ulp(b / dt[:, None] ** 2)


@pytest.mark.parametrize("bc", BC_TYPES, ids=str)
@pytest.mark.parametrize("x_kind", ["random", "uneven"])
def test_gpu_within_the_promise(gpu, bc, x_kind):
    rng = np.random.default_rng(7)
    x, y = data(bc, 12, (3,), rng, x_kind)
    ours = splinegpu.CubicSpline(x, y, bc_type=bc_of(bc, (3,)), context=gpu)
    theirs = SciPySpline(x, y, bc_type=bc_of(bc, (3,)))
    q = query(x, rng)
    extent = np.max(y.max(axis=0) - y.min(axis=0))
    for nu in (0, 1, 2):
        a = ours(q, nu)
        assert a.dtype == np.float32
        err = np.abs(a.astype(np.float64) - theirs(q, nu))
        bound = promise(theirs.c, x, q, nu, extent)
        assert np.all(err <= bound), (nu, np.max(err / bound))


def test_batched_splines_match_one_by_one():
    rng = np.random.default_rng(11)
    xs = [np.sort(rng.uniform(0, 10, n)) for n in (5, 9, 30)]
    ys = [rng.uniform(-1, 1, (len(x), 3)) for x in xs]
    qs = [rng.uniform(x[0], x[-1], 40) for x in xs]
    batch = splinegpu.CubicSplines(xs, ys, bc_type="natural")
    values, offsets = batch(qs, nu=1)
    assert list(offsets) == [0, 40, 80, 120]
    for i, (x, y, q) in enumerate(zip(xs, ys, qs)):
        np.testing.assert_array_equal(values[offsets[i]:offsets[i + 1]],
                                      splinegpu.CubicSpline(x, y, bc_type="natural")(q, 1))


def test_every_form_of_x_gives_scipys_values_and_shape():
    # The call's fast paths (a C-contiguous float64 array, a Python float) and the general
    # conversion (everything else) against SciPy: values and shapes.
    rng = np.random.default_rng(11)
    x = knots("random", 40, rng)
    y = rng.uniform(-3, 3, (40, 2))
    ours, theirs = splinegpu.CubicSpline(x, y), SciPySpline(x, y)
    grid = rng.uniform(x[0], x[-1], (6, 5))
    read_only = grid.copy()
    read_only.flags.writeable = False
    forms = [
        float(grid[0, 0]), np.float64(grid[0, 1]), np.array(grid[0, 2]), grid, grid[:, ::2],
        np.asfortranarray(grid), grid.astype(">f8"), read_only, grid.tolist(), grid[::-1, 1],
        np.sort(rng.uniform(x[0], x[-1], 5000)), rng.uniform(x[0], x[-1], 5000),
        np.array([x[0], x[-1], x[3]]), np.arange(3),
    ]
    for q in forms:
        a, b = ours(q), theirs(q)
        assert a.shape == b.shape, (np.shape(q), a.shape, b.shape)
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * np.abs(b).max() + 1e-300)


@pytest.mark.parametrize("kind", ["hermite", "pchip", "akima", "makima"])
@pytest.mark.parametrize("x_kind", ["random", "uneven"])
def test_hermite_kinds_match_scipy(kind, x_kind, cpu):
    from scipy.interpolate import Akima1DInterpolator, CubicHermiteSpline, PchipInterpolator

    rng = np.random.default_rng(len(kind) * 10 + len(x_kind))
    x = knots(x_kind, 12, rng)
    y = rng.uniform(-3, 3, (12, 3))
    y[4:7] = y[4]  # a flat run: PCHIP's and Akima's special cases
    fields = {}
    if kind == "hermite":
        tangents = rng.uniform(-2, 2, (12, 3))
        theirs = CubicHermiteSpline(x, y, tangents)
        fields = {"tangents": tangents}
    elif kind == "pchip":
        theirs = PchipInterpolator(x, y)
    else:
        theirs = Akima1DInterpolator(x, y, method=kind)
        fields = {"method": kind}
    q = query(x, rng)
    r = cpu.tessellate(y[None], "akima" if kind == "makima" else kind, t=x, at=q,
                       derivatives=2, **fields)
    for got, nu in ((r.points, 0), (r.d1, 1), (r.d2, 2)):
        want = theirs(q, nu)
        scale = np.abs(want).max()
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12 * scale + 1e-12,
                                   err_msg=f"{kind} nu={nu}")


@pytest.mark.parametrize("x_kind", ["random", "uneven"])
def test_nurbs_without_weights_is_scipys_bspline(x_kind, cpu):
    from scipy.interpolate import BSpline

    rng = np.random.default_rng(len(x_kind))
    n = 10
    knots_ = knots(x_kind, n + 4, rng)
    knots_[5] = knots_[4]  # a double interior knot: an empty span
    points = rng.uniform(-3, 3, (n, 2))
    theirs = BSpline(knots_, points, 3)
    q = rng.uniform(knots_[3], knots_[n], 300)
    r = cpu.tessellate(points[None], "nurbs", knots=knots_, at=q, derivatives=2)
    for got, nu in ((r.points, 0), (r.d1, 1), (r.d2, 2)):
        want = theirs(q, nu)
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-11 * np.abs(want).max(),
                                   err_msg=f"nu={nu}")
    with pytest.raises(ValueError, match=r'curve 0: "weights" must be finite and > 0'):
        cpu.tessellate(points[None], "nurbs", knots=knots_, weights=np.zeros(n))


@pytest.mark.parametrize("x_kind", ["random", "uneven"])
def test_weighted_nurbs_is_the_quotient_of_scipys_bsplines(x_kind, cpu):
    # A rational B-spline is BSpline(t, w P) / BSpline(t, w); its derivatives follow by the
    # quotient rule from SciPy's derivatives of both.
    from scipy.interpolate import BSpline

    rng = np.random.default_rng(7 + len(x_kind))
    n = 9
    knots_ = knots(x_kind, n + 4, rng)
    points = rng.uniform(-3, 3, (n, 3)) + 1e6
    weights = 10.0 ** rng.uniform(-1, 1, n)
    numerator = BSpline(knots_, points * weights[:, None], 3)
    denominator = BSpline(knots_, weights, 3)
    q = rng.uniform(knots_[3], knots_[n], 300)
    c = [numerator(q, nu) for nu in range(3)]
    w = [denominator(q, nu)[:, None] for nu in range(3)]
    p0 = c[0] / w[0]
    p1 = (c[1] - p0 * w[1]) / w[0]
    p2 = (c[2] - 2 * p1 * w[1] - p0 * w[2]) / w[0]
    r = cpu.tessellate(points[None], "nurbs", knots=knots_, weights=weights, at=q, derivatives=2)
    # SciPy's homogeneous sums near 1e6 carry its rounding: 1e-16 of 1e6 times the weights.
    for got, want, nu in ((r.points, p0, 0), (r.d1, p1, 1), (r.d2, p2, 2)):
        np.testing.assert_allclose(got, want, rtol=1e-7, atol=1e-7, err_msg=f"nu={nu}")
