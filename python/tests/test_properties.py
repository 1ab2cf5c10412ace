"""Property tests of the Python door: whatever the arguments, a call either returns a result
that holds together (and equals the same call written into fresh arrays), or raises
ValueError, TypeError or MemoryError. It never aborts the interpreter, raises a Rust panic
(pyo3's PanicException derives from BaseException, so `except Exception` would miss it) or
hands back values that a second route disagrees with.

SPLINEGPU_PROPERTY_CASES scales the case counts (CI runs the default: 10,000 in all)."""

import os

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import splinegpu

SCALE = float(os.environ.get("SPLINEGPU_PROPERTY_CASES", "1"))
REFUSED = (ValueError, TypeError, MemoryError)


def cases(n):
    return settings(max_examples=max(1, int(n * SCALE)), deadline=None, derandomize=True,
                    suppress_health_check=list(HealthCheck))


CPU = splinegpu.Context("cpu")


class Share:
    """How many of a property test's cases returned a result and how many were refused: a
    test that "returns or refuses" would pass without testing anything if every case were
    refused, so each asserts that at least `least` of its cases returned one."""

    def __init__(self, least: float):
        self.least, self.returned, self.refused = least, 0, 0

    def check(self):
        total = self.returned + self.refused
        assert total and self.returned >= self.least * total, (
            f"{self.returned} of {total} cases returned a result; at least {self.least:.0%} "
            f"should")

numbers = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True, width=64),
    st.sampled_from([0.0, 1.0, -1.0, 0.5, 1e-300, 1e300, 1e6]),
    st.integers(-3, 10),
)


@st.composite
def point_arrays(draw):
    """Points of every shape a caller might pass: mostly sound, some not."""
    curves = draw(st.integers(0, 3))
    n = draw(st.integers(0, 9))
    dim = draw(st.sampled_from([1, 2, 3, 64, 65]))
    form = draw(st.sampled_from(["array", "list", "ragged", "views", "fortran", "ints",
                                 "strings", "nested"]))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    base = rng.uniform(-2, 2, (curves, n, dim))
    if draw(st.booleans()):
        base[..., 0] *= draw(st.sampled_from([1.0, 1e6, 1e-6]))
    if form == "array":
        return base
    if form == "list":
        return [c.copy() for c in base]
    if form == "ragged":
        return [rng.uniform(-1, 1, (draw(st.integers(0, 9)), dim)) for _ in range(curves)]
    if form == "views":
        return list(base)
    if form == "fortran":
        return [np.asfortranarray(c) for c in base]
    if form == "ints":
        return base.astype(np.int32)
    if form == "strings":
        return [c.astype(str) for c in base]
    return [[list(p) for p in c] for c in base]


samplings = st.one_of(
    st.fixed_dictionaries({"per_segment": st.one_of(st.integers(-2, 40), numbers)}),
    st.fixed_dictionaries({"arc_length": st.one_of(st.integers(-2, 60), numbers)}),
    st.fixed_dictionaries({"tolerance": numbers}),
    st.fixed_dictionaries({"at": st.one_of(
        st.lists(numbers, max_size=6), st.just("0.5"), st.just([[0.5]]))}),
    st.just({}),
)

# "knots" and "weights" may be "fit": made right for the points (clamped knots, weights of
# every size), so that the rational paths are reached, not only the refusals.
kind_fields = st.fixed_dictionaries({}, optional={
    "ends": st.sampled_from(["control", "repeat", "closed", "open", 3]),
    "tension": numbers,
    "bias": numbers,
    "continuity": st.one_of(numbers, st.lists(numbers, max_size=10)),
    "t": st.lists(numbers, max_size=10),
    "matrix": st.sampled_from([np.eye(4), np.eye(3), [[1, 2, 3, 4]] * 4, "identity"]),
    "tangents": st.one_of(st.just("fit"), st.lists(numbers, max_size=6), st.just(np.eye(3))),
    "method": st.sampled_from(["akima", "makima", "bogus", 3, None]),
    "knots": st.one_of(st.just("fit"), st.lists(numbers, max_size=14)),
    "weights": st.one_of(st.just("fit"), st.lists(numbers, max_size=10)),
})


def fitted(points, fields, seed):
    """`fields` with each "fit" made right for `points` where they have one shape (n points of
    dim coordinates per curve), else left for the call to refuse."""
    fields = dict(fields)
    shape = np.shape(points) if isinstance(points, np.ndarray) else None
    rng = np.random.default_rng(seed)
    for name in ("knots", "weights", "tangents"):
        if not (isinstance(fields.get(name), str) and fields[name] == "fit"):
            continue
        if shape is None or len(shape) != 3:
            fields[name] = [0.5]
            continue
        curves, n, dim = shape
        if name == "knots":
            inner = np.cumsum(10 ** rng.uniform(-3, 3, max(n - 3, 1)))
            fields[name] = np.tile(np.concatenate([[0.0] * 4, inner[:-1], [inner[-1]] * 4]),
                                   (curves, 1))[:, :n + 4]
        elif name == "weights":
            fields[name] = 10 ** rng.uniform(-1, 1, (curves, n))
        else:
            fields[name] = rng.uniform(-2, 2, (curves, n, dim))
    return fields


def holds_together(r, derivatives):
    rows = r.t.shape[0]
    assert r.points.shape[0] == rows and r.curve_offsets[-1] == rows
    assert np.all(np.diff(r.curve_offsets) >= 0)
    for plane, wanted in ((r.d1, derivatives >= 1), (r.d2, derivatives >= 2)):
        assert (plane is not None) == wanted
        if wanted:
            assert plane.shape == r.points.shape


TESSELLATE_SHARE = Share(0.05)


def test_tessellate_returns_a_sound_result_or_refuses():
    tessellate_or_refuse()
    TESSELLATE_SHARE.check()


@cases(6000)
@given(points=point_arrays(), kind=st.sampled_from([*splinegpu.KIND_NAMES, "nurbs"]),
       fields=kind_fields, sampling=samplings,
       derivatives=st.one_of(st.integers(-1, 3), st.just(1.5), st.just(True)),
       seed=st.integers(0, 2**32 - 1))
def tessellate_or_refuse(points, kind, fields, sampling, derivatives, seed):
    fields = fitted(points, fields, seed)
    try:
        r = CPU.tessellate(points, kind, derivatives=derivatives, **fields, **sampling)
    except REFUSED:
        TESSELLATE_SHARE.refused += 1
        return
    TESSELLATE_SHARE.returned += 1
    holds_together(r, derivatives)
    # The same call into the result's own arrays gives the same values.
    again = CPU.tessellate(points, kind, derivatives=derivatives, **fields, **sampling,
                           out=splinegpu.Tessellation(
                               r.t.copy(), r.points.copy(),
                               None if r.d1 is None else r.d1.copy(),
                               None if r.d2 is None else r.d2.copy(),
                               r.curve_offsets.copy()))
    for a, b in zip((r.t, r.points, r.d1, r.d2), (again.t, again.points, again.d1, again.d2)):
        if a is not None:
            np.testing.assert_array_equal(a, b)


@st.composite
def out_arrays(draw, good):
    """`good`'s arrays, one of them spoiled the way callers spoil them."""
    arrays = {"t": good.t.copy(), "points": good.points.copy(), "d1": good.d1.copy(),
              "d2": None, "curve_offsets": good.curve_offsets.copy()}
    name = draw(st.sampled_from(list(arrays)))
    how = draw(st.sampled_from(["read-only", "fortran", "transposed", "float32", "int32",
                                "shorter", "strided", "alias", "list", "none", "same"]))
    a = arrays[name]
    if a is None or how == "same":
        return splinegpu.Tessellation(**arrays)
    if how == "read-only":
        a.flags.writeable = False
    elif how == "fortran" and a.ndim == 2:
        a = np.asfortranarray(a)
    elif how == "transposed" and a.ndim == 2:
        a = np.ascontiguousarray(a.T)
    elif how == "float32":
        a = a.astype(np.float32)
    elif how == "int32":
        a = a.astype(np.int32)
    elif how == "shorter":
        a = a[:-1].copy()
    elif how == "strided":
        a = np.repeat(a, 2, axis=0)[::2]
    elif how == "alias":
        a = arrays["points"] if name != "points" else arrays["d1"]
    elif how == "list":
        a = a.tolist()
    elif how == "none":
        a = None
    arrays[name] = a
    return splinegpu.Tessellation(**arrays)


GOOD_CURVES = np.random.default_rng(3).uniform(-1, 1, (3, 7, 2))
GOOD = CPU.tessellate(GOOD_CURVES, per_segment=5, derivatives=1)


def used_right_or_refused(ctx, good, out, share: Share):
    """`out` filled with `good`'s values by the same call on `ctx`, or refused."""
    try:
        r = ctx.tessellate(GOOD_CURVES, per_segment=5, derivatives=1, out=out)
    except REFUSED:
        share.refused += 1
        return
    share.returned += 1
    for a, b in ((r.t, good.t), (r.points, good.points), (r.d1, good.d1),
                 (r.curve_offsets, good.curve_offsets)):
        np.testing.assert_array_equal(a, b)


def test_out_is_used_right_or_refused():
    share = Share(0.2)

    @cases(2000)
    @given(out=out_arrays(GOOD))
    def run(out):
        used_right_or_refused(CPU, GOOD, out, share)

    run()
    share.check()


CUBIC_SHARE = Share(0.03)


def test_cubic_spline_fits_and_evaluates_or_refuses():
    cubic_spline_or_refuse()
    CUBIC_SHARE.check()


@cases(2000)
@given(n=st.one_of(st.integers(0, 8), st.integers(4, 8)),
       trailing=st.sampled_from([(), (2,), (3, 2), (65,)]),
       # Every axis y has (0 or -1) half the time, any other value or type the rest.
       axis=st.one_of(st.sampled_from([0, -1]), st.integers(-4, 3), st.just(1.5), st.just(True),
                      st.sampled_from([0, -1]), st.sampled_from([0, -1])),
       bc=st.sampled_from(["not-a-knot", "natural", "clamped", "periodic", "bogus",
                           ((1, 0.0), (1, 0.0)), ((2, 0.0), (2, 0.0)), 3]),
       # Sorted x three times in eight: enough cases fit and evaluate to test the results.
       x_kind=st.sampled_from(["sorted", "sorted", "sorted", "unsorted", "repeated", "nan",
                               "complex", "2-d"]),
       nu=st.one_of(st.integers(-1, 3), st.just(0.5)), seed=st.integers(0, 2**32 - 1))
def cubic_spline_or_refuse(n, trailing, axis, bc, x_kind, nu, seed):
    rng = np.random.default_rng(seed)
    x = np.sort(rng.uniform(0, 10, n))
    if x_kind == "unsorted":
        x = x[::-1]
    elif x_kind == "repeated" and n > 1:
        x[1] = x[0]
    elif x_kind == "nan" and n:
        x[-1] = np.nan
    elif x_kind == "complex":
        x = x + 0j
    elif x_kind == "2-d":
        x = x[:, None]
    y = rng.uniform(-1, 1, (n, *trailing))
    if bc == "periodic" and n:
        y[-1] = y[0]
    try:
        y = np.moveaxis(y, 0, axis) if isinstance(axis, int) and -y.ndim <= axis < y.ndim else y
    except (TypeError, np.exceptions.AxisError):
        pass
    try:
        s = splinegpu.CubicSpline(x, y, axis=axis, bc_type=bc)
    except REFUSED:
        CUBIC_SHARE.refused += 1
        return
    xq = rng.uniform(x.min(), x.max(), (2, 3))
    try:
        values = s(xq, nu=nu)
    except REFUSED:
        CUBIC_SHARE.refused += 1
        return
    CUBIC_SHARE.returned += 1
    # SciPy's shape: y's axes before `axis`, x's, then y's after it.
    shape = np.shape(y)
    assert values.shape == (*shape[:s.axis], *xq.shape, *shape[s.axis + 1:])


@pytest.fixture(scope="module")
def gpu_good(gpu):
    return gpu, gpu.tessellate(GOOD_CURVES, per_segment=5, derivatives=1)


def test_out_on_the_gpu_is_used_right_or_refused(gpu_good):
    gpu, good = gpu_good
    share = Share(0.2)

    @cases(300)
    @given(data=st.data())
    def run(data):
        used_right_or_refused(gpu, good, data.draw(out_arrays(good)), share)

    run()
    share.check()


@cases(300)
@given(n=st.integers(4, 12), dim=st.integers(1, 3), seed=st.integers(0, 2**32 - 1),
       multiplicity=st.integers(1, 3), decades=st.integers(0, 6),
       samples=st.sampled_from(["at", "per_segment"]))
def test_random_weighted_nurbs_are_scipys_quotient(n, dim, seed, multiplicity, decades,
                                                   samples):
    """A random rational B-spline (clamped knots whose spacings span `decades` decades, one
    interior knot repeated `multiplicity` times, weights in [0.1, 10]) at random or grid t:
    BSpline(t, w P) / BSpline(t, w) and its quotient-rule derivatives, on the CPU."""
    from scipy.interpolate import BSpline

    rng = np.random.default_rng(seed)
    # n - 4 interior knots and the end: n + 4 in all.
    inner = np.cumsum(10.0 ** rng.uniform(-decades / 2, decades / 2, n - 3))
    interior, end = inner[:-1], inner[-1]
    if n > 4 and multiplicity > 1:
        j = rng.integers(0, n - 4)
        interior = np.sort(np.concatenate([interior, [interior[j]] * (multiplicity - 1)]))
        interior = interior[: n - 4]
    knots = np.concatenate([[0.0] * 4, interior, [end] * 4])
    points = rng.uniform(-3, 3, (n, dim))
    weights = 10.0 ** rng.uniform(-1, 1, n)
    if samples == "at":
        r = CPU.tessellate(points[None], "nurbs", knots=knots, weights=weights, derivatives=2,
                           at=rng.uniform(knots[3], knots[n], 50))
    else:
        r = CPU.tessellate(points[None], "nurbs", knots=knots, weights=weights, derivatives=2,
                           per_segment=5)
    numerator = BSpline(knots, points * weights[:, None], 3)
    denominator = BSpline(knots, weights, 3)
    c = [numerator(r.t, nu) for nu in range(3)]
    w = [denominator(r.t, nu)[:, None] for nu in range(3)]
    p0 = c[0] / w[0]
    p1 = (c[1] - p0 * w[1]) / w[0]
    p2 = (c[2] - 2 * p1 * w[1] - p0 * w[2]) / w[0]
    for got, want, nu in ((r.points, p0, 0), (r.d1, p1, 1), (r.d2, p2, 2)):
        # SciPy's sums carry its own rounding, scaled by the largest value of the order.
        np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-9 * np.abs(want).max(),
                                   err_msg=f"nu={nu}")
