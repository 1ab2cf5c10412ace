"""`splinegpu.interpolate` against `scipy.interpolate`: the Hermite-family classes
(CubicHermiteSpline, PchipInterpolator, Akima1DInterpolator with both methods) and
pchip_interpolate, for 1-D and N-D y, every axis, every extrapolate mode, nu 0 to 3, uneven x
(neighbouring spacings to 1e6 apart), on the CPU (1e-10 of the largest value, far
extrapolation included) and on the GPU (the promise)."""

import pickle

import numpy as np
import pytest

import splinegpu
import splinegpu.interpolate as si

interpolate = pytest.importorskip("scipy.interpolate")


def data(shape, seed, ratio=1e3):
    rng = np.random.default_rng(seed)
    h = ratio ** rng.uniform(-0.5, 0.5, 13)
    x = np.concatenate([[1.0], 1.0 + np.cumsum(h)])
    y = rng.uniform(-2, 2, (len(x), *shape))
    return x, y, rng


def queries(x, rng):
    lo, hi = x[0], x[-1]
    span = hi - lo
    return np.concatenate([rng.uniform(lo, hi, 60), x, [lo - 1e-14 * span, np.nan],
                           rng.uniform(lo - span / 2, lo, 5), rng.uniform(hi, hi + span / 2, 5)])


def pairs(x, y, axis, rng, context=None):
    """(name, ours, SciPy's) for every class on the same data, ours on `context`."""
    dydx = rng.uniform(-3, 3, y.shape)
    on = {"context": context}
    return [
        ("hermite", lambda **kw: si.CubicHermiteSpline(x, y, dydx, axis=axis, **on, **kw),
         lambda **kw: interpolate.CubicHermiteSpline(x, y, dydx, axis=axis, **kw)),
        ("pchip", lambda **kw: si.PchipInterpolator(x, y, axis=axis, **on, **kw),
         lambda **kw: interpolate.PchipInterpolator(x, y, axis=axis, **kw)),
        ("akima", lambda **kw: si.Akima1DInterpolator(x, y, axis=axis, **on, **kw),
         lambda **kw: interpolate.Akima1DInterpolator(x, y, axis=axis, **kw)),
        ("makima",
         lambda **kw: si.Akima1DInterpolator(x, y, axis=axis, method="makima", **on, **kw),
         lambda **kw: interpolate.Akima1DInterpolator(x, y, axis=axis, method="makima", **kw)),
    ]


def assert_scipy(got, want, what, tolerance=1e-10):
    assert got.shape == want.shape, what
    scale = np.nanmax(np.abs(want)) if np.isfinite(want).any() else 1.0
    np.testing.assert_allclose(got, want, rtol=0, atol=tolerance * max(scale, 1e-300),
                               equal_nan=True, err_msg=what)


@pytest.mark.parametrize("shape,axis", [((), 0), ((3,), 0), ((2, 3), -1), ((2, 3), 1)])
@pytest.mark.parametrize("ratio", [1.0, 1e3, 1e6])
def test_every_class_is_scipys(shape, axis, ratio):
    x, y, rng = data(shape, seed=len(shape) + axis, ratio=ratio)
    y = np.moveaxis(y, 0, axis)
    q = queries(x, rng)
    for name, ours, theirs in pairs(x, y, axis, rng):
        for extrapolate in (None, True, False, "periodic"):
            if extrapolate == "periodic" and name.endswith("akima"):
                continue  # SciPy's Akima takes a bool only
            a, b = ours(extrapolate=extrapolate), theirs(extrapolate=extrapolate)
            assert a.extrapolate == b.extrapolate, name
            np.testing.assert_allclose(a.c, b.c, rtol=0, atol=1e-12 * np.abs(b.c).max())
            for nu in range(4):
                assert_scipy(a(q, nu), b(q, nu), f"{name}, {extrapolate}, nu={nu}")
                if nu:
                    assert_scipy(a.derivative(nu)(q), b.derivative(nu)(q),
                                 f"{name}.derivative({nu})")


def test_pchip_interpolate_is_scipys():
    x, y, rng = data((2,), 3)
    q = rng.uniform(x[0], x[-1], 30)
    assert_scipy(si.pchip_interpolate(x, y, q), interpolate.pchip_interpolate(x, y, q), "der 0")
    assert_scipy(si.pchip_interpolate(x, y, q, der=2),
                 interpolate.pchip_interpolate(x, y, q, der=2), "der 2")
    for got, want in zip(si.pchip_interpolate(x, y, q, der=[0, 1, 3]),
                         interpolate.pchip_interpolate(x, y, q, der=[0, 1, 3])):
        assert_scipy(got, want, "der [0, 1, 3]")


def test_scipy_code_runs_unchanged_with_si():
    # A typical SciPy snippet, with `si` for scipy.interpolate.
    x = np.linspace(0, 2 * np.pi, 20)
    y = np.column_stack([np.sin(x), np.cos(x)])
    xs = np.linspace(-1, 7, 200)
    results = []
    for module in (si, interpolate):
        cs = module.CubicSpline(x, y, bc_type=((2, [0.0, 0.0]), (1, [1.0, -1.0])))
        p = module.PchipInterpolator(x, y[:, 0])
        a = module.Akima1DInterpolator(x, y, method="makima", extrapolate=True)
        h = module.CubicHermiteSpline(x, y[:, 1], -np.sin(x))
        results.append([cs(xs), cs(xs, 2), p(xs, 1), a(xs), h(xs, 3), cs.derivative()(xs)])
    for ours, theirs in zip(*results):
        assert_scipy(ours, theirs, "snippet")


def test_the_gpu_keeps_the_promise(gpu):
    x, y, rng = data((3,), 11)
    q = queries(x, rng)
    for name, ours, theirs in pairs(x, y, 0, rng, context=gpu):
        a, b = ours(extrapolate=True), theirs(extrapolate=True)
        for nu in range(3):
            got = a(q, nu)
            assert got.dtype == np.float32
            assert_scipy(got, b(q, nu), f"GPU {name}, nu={nu}", tolerance=2e-5)


def test_the_classes_pickle_and_refuse_what_scipys_refuse(cpu):
    x, y, rng = data((2,), 5)
    q = queries(x, rng)
    for spline in (si.PchipInterpolator(x, y, context=cpu),
                   si.Akima1DInterpolator(x, y, method="makima"),
                   si.CubicHermiteSpline(x, y * 1j, y)):
        again = pickle.loads(pickle.dumps(spline))
        assert type(again) is type(spline)
        for nu in range(4):
            np.testing.assert_array_equal(again(q, nu), spline(q, nu))
    with pytest.raises(ValueError, match="y: PchipInterpolator only works with real values"):
        si.PchipInterpolator(x, y * 1j)
    with pytest.raises(ValueError, match="y: Akima1DInterpolator only works with real values"):
        si.Akima1DInterpolator(x, y * 1j)
    with pytest.raises(NotImplementedError, match="`method`=linear is unsupported"):
        si.Akima1DInterpolator(x, y, method="linear")
    with pytest.raises(ValueError, match=r"bc_type: an end's value must have y's other axes' "
                       r"shape \(2,\), got \(\)"):
        si.CubicSpline(x, y, bc_type=((1, 0.5), "natural"))
    with pytest.raises(ValueError, match=r"dydx: must have y's shape \(14, 2\)"):
        si.CubicHermiteSpline(x, y, y[:, 0])
    with pytest.raises(ValueError, match=r'"t" must be strictly increasing'):
        si.PchipInterpolator(x[::-1], y)
    assert splinegpu.CubicSpline is si.CubicSpline


def test_batches_equal_their_single_splines_on_ragged_knots(cpu):
    rng = np.random.default_rng(21)
    xs = [np.cumsum(10 ** rng.uniform(-2, 2, n)) for n in rng.integers(2, 40, 30)]
    ys = [rng.uniform(-1, 1, (len(x), 3)) for x in xs]
    dydxs = [rng.uniform(-1, 1, (len(x), 3)) for x in xs]
    qs = [rng.uniform(x[0], x[-1], rng.integers(0, 50)) for x in xs]
    batches = [
        (si.PchipInterpolators(xs, ys), lambda x, y, d: si.PchipInterpolator(x, y)),
        (si.Akima1DInterpolators(xs, ys, method="makima"),
         lambda x, y, d: si.Akima1DInterpolator(x, y, method="makima")),
        (si.CubicHermiteSplines(xs, ys, dydxs, context=cpu),
         lambda x, y, d: si.CubicHermiteSpline(x, y, d)),
        (si.CubicSplines(xs, ys, bc_type=("natural", (1, 0.5))),
         lambda x, y, d: si.CubicSpline(x, y, bc_type=("natural", (1, np.full(3, 0.5))))),
    ]
    for batch, single in batches:
        assert len(batch) == len(xs)
        for nu in range(3):
            values, offsets = batch(qs, nu)
            for i, (x, y, d, q) in enumerate(zip(xs, ys, dydxs, qs)):
                np.testing.assert_array_equal(values[offsets[i]:offsets[i + 1]],
                                              single(x, y, d)(q, nu))
        again = pickle.loads(pickle.dumps(batch))
        np.testing.assert_array_equal(again(qs)[0], batch(qs)[0])
    with pytest.raises(ValueError, match="curve 3"):
        si.PchipInterpolators([*xs[:3], xs[3][::-1]], ys[:4])


@pytest.mark.parametrize("shape", [(), (2, 3)])
def test_integrals_are_scipys_in_every_extrapolate_mode(shape):
    x, y, _ = data(shape, seed=31 + len(shape))
    periodic_y = y.copy()
    periodic_y[-1] = periodic_y[0]
    lo, hi = x[0], x[-1]
    span = hi - lo
    bounds = [(lo, hi), (hi, lo), (x[3], x[3]), (x[2] + 0.3, x[7] - 0.1), (lo - span / 3, x[4]),
              (x[5], hi + span / 2), (lo - 2.5 * span, hi + 1.7 * span), (hi + 1, lo - 4 * span)]
    splines = [
        (si.CubicSpline(x, periodic_y, bc_type="periodic"),
         interpolate.CubicSpline(x, periodic_y, bc_type="periodic")),
        (si.CubicSpline(x, y * (1 - 2j), bc_type=((2, np.full(shape, 1.0)), "not-a-knot")),
         interpolate.CubicSpline(x, y * (1 - 2j),
                                 bc_type=((2, np.full(shape, 1.0)), "not-a-knot"))),
        (si.PchipInterpolator(x, y), interpolate.PchipInterpolator(x, y)),
        (si.Akima1DInterpolator(x, y, method="makima"),
         interpolate.Akima1DInterpolator(x, y, method="makima")),
    ]
    for ours, theirs in splines:
        for extrapolate in (None, True, False, "periodic"):
            for a, b in bounds:
                got = ours.integrate(a, b, extrapolate=extrapolate)
                want = theirs.integrate(a, b, extrapolate=extrapolate)
                # Within 1e-12 of the integral of the largest value over the interval, or
                # of the integral itself (the end pieces grow far past the knots).
                scale = np.abs(y).max() * max(abs(b - a), span)
                np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12 * scale,
                                           equal_nan=True,
                                           err_msg=f"{type(ours).__name__} {extrapolate} "
                                                   f"[{a}, {b}]")


def test_batch_integrals_are_their_single_splines(cpu):
    rng = np.random.default_rng(23)
    xs = [np.cumsum(10 ** rng.uniform(-2, 2, n)) for n in rng.integers(2, 40, 25)]
    ys = [rng.uniform(-1, 1, (len(x), 2)) for x in xs]
    for y in ys:
        y[-1] = y[0]  # periodic splines too
    a = np.array([x[0] + rng.uniform(-0.5, 1.2) * (x[-1] - x[0]) for x in xs])
    b = np.array([x[0] + rng.uniform(-2.0, 3.0) * (x[-1] - x[0]) for x in xs])
    batches = [
        (si.PchipInterpolators(xs, ys), lambda x, y: si.PchipInterpolator(x, y)),
        (si.Akima1DInterpolators(xs, ys), lambda x, y: si.Akima1DInterpolator(x, y)),
        (si.CubicSplines(xs, ys, bc_type="periodic", context=cpu),
         lambda x, y: si.CubicSpline(x, y, bc_type="periodic")),
    ]
    for batch, single in batches:
        for extrapolate in (None, True, False, "periodic"):
            for lo, hi in ((a, b), (2.5, b), (a, -1.0)):
                got = batch.integrate(lo, hi, extrapolate=extrapolate)
                assert got.shape == (len(xs), 2)
                for i, (x, y) in enumerate(zip(xs, ys)):
                    want = single(x, y).integrate(np.broadcast_to(lo, a.shape)[i],
                                            np.broadcast_to(hi, b.shape)[i],
                                            extrapolate=extrapolate)
                    np.testing.assert_allclose(got[i], want, rtol=1e-12,
                                               atol=1e-12 * np.abs(want).max(initial=1.0),
                                               equal_nan=True,
                                               err_msg=f"{extrapolate}, spline {i}")
        again = pickle.loads(pickle.dumps(batch))
        np.testing.assert_array_equal(again.integrate(a, b), batch.integrate(a, b))
    with pytest.raises(ValueError, match=r"a: must be a number or one per spline \(25\)"):
        batches[0][0].integrate(np.zeros(3), 1.0)


def test_interp1d_refuses_a_negative_order_naming_it():
    # IndexError "index 10 is out of bounds" before.
    x = np.linspace(0, 1, 10)
    with pytest.raises(ValueError, match="kind: a spline's order must be >= 0, got -1"):
        si.interp1d(x, x, kind=-1)
