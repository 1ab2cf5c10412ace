"""Context.tessellate: the CLI's numbers, ragged batches, every sampling, out= reuse, threads,
and a located ValueError for every class of bad input."""

import json
import os
import pathlib
import subprocess
import tempfile
import threading

import numpy as np
import pytest

import splinegpu

ROOT = pathlib.Path(__file__).resolve().parents[2]


def cli():
    """The command line scripts/test-python.sh builds (target/debug), else a release build."""
    for profile in ("debug", "release"):
        path = ROOT / "target" / profile / "splinegpu"
        if path.exists():
            return path
    if os.environ.get("CI") == "true":
        raise AssertionError("no target/*/splinegpu: run cargo test first")
    pytest.skip("no splinegpu binary built")


def cli_npz(document):
    with tempfile.TemporaryDirectory() as folder:
        doc, out = pathlib.Path(folder, "doc.json"), pathlib.Path(folder, "out.npz")
        doc.write_text(json.dumps(document))
        subprocess.run([str(cli()), "tessellate", str(doc), "-o", str(out), "--backend", "cpu"],
                       check=True, capture_output=True)
        with np.load(out) as npz:
            return {k: npz[k] for k in npz.files}


CASES = [
    # kind, fields, sampling (python keyword, document object)
    ("catmull-rom", {}, ("per_segment", 7)),
    ("cardinal", {"tension": 0.3, "ends": "closed"}, ("arc_length", 50)),
    ("bspline", {"ends": "repeat"}, ("tolerance", 0.01)),
    ("beta", {"bias": 1.5, "tension": 2.0}, ("per_segment", 3)),
    ("beta", {"bias": [1, 2, 0.5, 1, 3, 0.8, 1, 1.5, 0.3, 2],
              "tension": [0, 1, 4, 0, 2, 0, 8, 1, 0, 3], "ends": "repeat"}, ("tolerance", 0.01)),
    ("tensioned-bspline", {"tension": 4.0}, ("per_segment", 5)),
    ("bezier", {}, ("arc_length", 9)),
    ("natural", {}, ("per_segment", 4)),
    ("not-a-knot", {}, ("tolerance", 0.05)),
    ("matrix", {"matrix": [[-1, 3, -3, 1], [3, -6, 3, 0], [-3, 0, 3, 0], [1, 4, 1, 0]]},
     ("per_segment", 6)),
]


@pytest.mark.parametrize("kind,fields,sampling", CASES,
                         ids=[f"{c[0]}-{i}" for i, c in enumerate(CASES)])
def test_equal_to_the_cli_npz(cpu, kind, fields, sampling):
    rng = np.random.default_rng(1)
    n = 10
    curves = [rng.uniform(-3, 3, (n, 2)) for _ in range(3)]
    name, value = sampling
    document = {
        "derivatives": 2,
        "sampling": {name: value},
        "curves": [dict(kind=kind, points=c.tolist(), **fields) for c in curves],
    }
    want = cli_npz(document)
    got = cpu.tessellate(curves, kind, derivatives=2, **{name: value}, **fields)
    for key in ("t", "points", "d1", "d2", "curve_offsets"):
        np.testing.assert_array_equal(getattr(got, key), want[key], err_msg=key)


def test_interpolating_knots_and_clamped_derivatives_equal_the_cli(cpu):
    rng = np.random.default_rng(2)
    t = [np.cumsum(rng.uniform(0.1, 2, 6)) for _ in range(2)]
    pts = [rng.uniform(-1, 1, (6, 3)) for _ in range(2)]
    d0, d1 = [[1, 0, 0], [0, 1, 0]], [[0, 0, 1], [1, 1, 1]]
    document = {"derivatives": 1, "sampling": {"at": [float(t[0][2]), float(t[0][0])]},
                "curves": [{"kind": "clamped", "points": p.tolist(), "t": k.tolist(),
                            "start_derivative": a, "end_derivative": b,
                            "sampling": {"at": [float(k[1]), float(k[-1]), float(k[0])]}}
                           for p, k, a, b in zip(pts, t, d0, d1)]}
    want = cli_npz(document)
    at = [[k[1], k[-1], k[0]] for k in t]
    got = cpu.tessellate(pts, "clamped", t=t, start_derivative=d0, end_derivative=d1, at=at,
                         derivatives=1)
    for key in ("t", "points", "d1", "curve_offsets"):
        np.testing.assert_array_equal(getattr(got, key), want[key], err_msg=key)


def test_ragged_batch_is_each_curve_alone(cpu):
    rng = np.random.default_rng(3)
    curves = [rng.uniform(-1, 1, (n, 3)) for n in (4, 17, 6, 40)]
    whole = cpu.tessellate(curves, "bspline", arc_length=33, derivatives=1)
    assert whole.curve_offsets.tolist() == [0, 33, 66, 99, 132]
    for c, points in enumerate(curves):
        alone = cpu.tessellate([points], "bspline", arc_length=33, derivatives=1)
        part = whole.curve(c)
        np.testing.assert_array_equal(part.points, alone.points)
        np.testing.assert_array_equal(part.t, alone.t)
        np.testing.assert_array_equal(part.d1, alone.d1)


def test_gpu_gives_float32_within_the_cpu_values(cpu, gpu):
    rng = np.random.default_rng(4)
    curves = rng.uniform(-1, 1, (50, 8, 3))
    a = cpu.tessellate(curves, per_segment=10, derivatives=2)
    b = gpu.tessellate(curves, per_segment=10, derivatives=2)
    assert b.points.dtype == np.float32 and b.t.dtype == np.float64
    np.testing.assert_array_equal(a.t, b.t)
    np.testing.assert_array_equal(a.curve_offsets, b.curve_offsets)
    assert np.max(np.abs(a.points - b.points)) < 1e-5 * 2


@pytest.mark.parametrize("backend", ["cpu", "gpu"])
def test_out_reuses_the_arrays(cpu, gpu, backend):
    ctx = cpu if backend == "cpu" else gpu
    rng = np.random.default_rng(5)
    first = ctx.tessellate(rng.uniform(-1, 1, (20, 6, 2)), per_segment=4, derivatives=1)
    arrays = [first.t, first.points, first.d1, first.curve_offsets]
    curves = rng.uniform(-1, 1, (20, 6, 2))
    again = ctx.tessellate(curves, per_segment=4, derivatives=1, out=first)
    assert [again.t, again.points, again.d1, again.curve_offsets] == arrays or all(
        x is y for x, y in zip([again.t, again.points, again.d1, again.curve_offsets], arrays))
    fresh = ctx.tessellate(curves, per_segment=4, derivatives=1)
    np.testing.assert_array_equal(again.points, fresh.points)
    np.testing.assert_array_equal(again.d1, fresh.d1)
    np.testing.assert_array_equal(again.t, fresh.t)
    with pytest.raises(ValueError, match="out"):
        ctx.tessellate(curves, per_segment=5, derivatives=1, out=first)


def test_threads_share_one_context(cpu, gpu):
    rng = np.random.default_rng(6)
    batches = [rng.uniform(-1, 1, (30, 7, 3)) for _ in range(8)]
    for ctx in (cpu, gpu):
        want = [ctx.tessellate(b, per_segment=9).points for b in batches]
        got = [None] * len(batches)

        def work(i, ctx=ctx, got=got):
            got[i] = ctx.tessellate(batches[i], per_segment=9).points

        threads = [threading.Thread(target=work, args=(i,)) for i in range(len(batches))]
        for th in threads:
            th.start()
        for th in threads:
            th.join()
        for w, g in zip(want, got):
            np.testing.assert_array_equal(w, g)


BAD = [
    ({"kind": "spiral"}, r'"kind" is unknown: "spiral"'),
    ({"kind": "bspline", "tension": 1.0}, r'curve 0: "tension" is not a field of a "bspline"'),
    ({"kind": "catmull-rom", "ends": "loop"}, r'"ends" must be'),
    ({"kind": "natural", "per_segment": 0}, r'curve 0: "per_segment"'),
    ({"kind": "natural", "tolerance": -1.0}, r'curve 0: "tolerance"'),
    ({"kind": "natural", "tolerance": float("nan")}, r'curve 0: "tolerance"'),
    ({"kind": "natural", "arc_length": 1}, r'curve 0: "arc_length"'),
    ({"kind": "natural", "at": [[0.5], [99.0]]}, r'curve 1: "at"'),
    ({"kind": "natural", "derivatives": 3}, r"derivatives"),
    ({"kind": "natural", "per_segment": 2, "at": [0.5]}, r"sampling: give one of"),
    ({"kind": "clamped"}, r'"start_derivative" is missing'),
    ({"kind": "natural", "t": [[0, 1, 1, 2, 3], [0, 1, 2, 3, 4]]}, r'curve 0: "t"'),
    ({"kind": "matrix"}, r'"matrix" is missing'),
]


@pytest.mark.parametrize("kwargs,message", BAD, ids=[m for _, m in BAD])
def test_bad_input_raises_a_located_value_error(cpu, kwargs, message):
    rng = np.random.default_rng(7)
    curves = rng.uniform(-1, 1, (2, 5, 2))
    kind = kwargs.pop("kind")
    with pytest.raises(ValueError, match=message):
        cpu.tessellate(curves, kind, **kwargs)


def test_bad_points_name_their_curve(cpu):
    good = np.zeros((5, 2))
    bad = good.copy()
    bad[3, 1] = np.nan
    with pytest.raises(ValueError, match=r"curve 1: .*points"):
        cpu.tessellate([good + np.arange(5)[:, None], bad], "natural")
    with pytest.raises(ValueError, match=r"curve 0: .*points"):
        cpu.tessellate([np.zeros((2, 2))], "catmull-rom")
    with pytest.raises(ValueError, match=r"points: must be"):
        cpu.tessellate(np.zeros((4, 2)), "catmull-rom")


def test_backends_and_bc_types_are_checked():
    with pytest.raises(ValueError, match="backend"):
        splinegpu.Context("tpu")
    x = np.arange(5.0)
    with pytest.raises(ValueError, match="bc_type"):
        splinegpu.CubicSpline(x, x, bc_type="free")
    with pytest.raises(ValueError, match=r'"t"'):
        splinegpu.CubicSpline(np.array([0, 1, 1, 2, 3.0]), x)
    spline = splinegpu.CubicSpline(x, x)
    with pytest.raises(ValueError, match="nu"):
        spline(1.0, nu=-1)


def test_complex_values_are_refused_not_cut_to_their_real_part(cpu):
    # (CubicSpline's y may be complex, as SciPy's: test_scipy.py.)
    import warnings

    z = np.arange(5.0) * (1 + 1j)
    x = np.arange(5.0)
    calls = {
        "points": lambda: cpu.tessellate(np.zeros((1, 4, 2), dtype=complex), "bspline"),
        'curve 0: "points"': lambda: cpu.tessellate([np.zeros((4, 2), dtype=complex)], "bspline"),
        "at": lambda: cpu.tessellate(np.zeros((1, 4, 2)), "bspline", at=[0.5 + 0j]),
        "x": lambda: splinegpu.CubicSpline(z, x),
        "bc_type": lambda: splinegpu.CubicSplines([x], [x[:, None]], bc_type=((1, 1j), (1, 0))),
        "xs": lambda: splinegpu.CubicSplines([x], [x[:, None]])([z]),
        "ys": lambda: splinegpu.CubicSplines([x], [z[:, None]]),
    }
    with warnings.catch_warnings():
        # NumPy warns when it casts complex to float; nothing may be cast.
        warnings.simplefilter("error")
        for name, call in calls.items():
            with pytest.raises(ValueError, match=f"^{name}: complex values are not supported"):
                call()


@pytest.mark.parametrize("backend", ["cpu", "gpu"])
@pytest.mark.parametrize("sampling", [{"per_segment": 2**32 - 1}, {"per_segment": 10**8},
                                      {"arc_length": 10**9}])
def test_a_result_larger_than_memory_is_refused_before_it_is_allocated(cpu, gpu, backend,
                                                                        sampling):
    # Three curves of 1,000 segments: per_segment=10**8 asks for 3·10**11 samples, terabytes
    # of arrays, and arc_length=10**9 for 3·10**9 samples, 60 GB or more. The call must raise
    # MemoryError naming the sampling, the samples and the bytes, not abort.
    ctx = cpu if backend == "cpu" else gpu
    curve = np.random.default_rng(9).uniform(-1, 1, (3, 1003, 3))
    name, value = next(iter(sampling.items()))
    with pytest.raises(MemoryError, match=rf"{name}={value} gives \d+ samples, whose arrays "
                                          r"need \d+ bytes"):
        ctx.tessellate(curve, "bspline", **sampling)


def test_a_fresh_result_is_the_same_as_one_written_into_out(cpu, gpu):
    # Fresh results are NumPy's own arrays filled in place; out= fills given ones. Same values.
    curves = np.random.default_rng(10).uniform(-1, 1, (50, 9, 2))
    for ctx in (cpu, gpu):
        fresh = ctx.tessellate(curves, "catmull-rom", per_segment=7, derivatives=2)
        again = ctx.tessellate(curves, "catmull-rom", per_segment=7, derivatives=2, out=fresh)
        want = ctx.tessellate(curves, "catmull-rom", per_segment=7, derivatives=2)
        for a, b in zip((again.t, again.points, again.d1, again.d2, again.curve_offsets),
                        (want.t, want.points, want.d1, want.d2, want.curve_offsets)):
            np.testing.assert_array_equal(a, b)
        assert fresh.points.flags.c_contiguous and fresh.points.flags.writeable


@pytest.mark.parametrize("backend", ["cpu", "gpu"])
def test_out_arrays_that_cannot_hold_the_result_are_refused_by_name(cpu, gpu, backend):
    # Each would have been written wrongly or crashed: read-only (a pyo3 panic), one array
    # given twice (a panic on the CPU, wrong values on the GPU), Fortran order or (D, N) shape
    # (wrong values). Each is a ValueError naming the array, and nothing is written.
    ctx = cpu if backend == "cpu" else gpu
    curves = np.random.default_rng(11).uniform(-1, 1, (4, 6, 3))
    good = ctx.tessellate(curves, per_segment=5, derivatives=1)

    def out(**replace):
        arrays = {"t": good.t.copy(), "points": good.points.copy(), "d1": good.d1.copy(),
                  "d2": None, "curve_offsets": good.curve_offsets.copy()}
        arrays.update(replace)
        return splinegpu.Tessellation(**arrays)

    read_only = good.points.copy()
    read_only.flags.writeable = False
    cases = [
        (out(points=read_only), r"out: points is not writeable"),
        (out(d1=None), r"out: a derivative array"),
        (out(points=np.asfortranarray(good.points)), r"out: points must be a C-ordered"),
        (out(points=np.ascontiguousarray(good.points.T).T), r"out: points must be a C-ordered"),
        (out(points=np.zeros(good.points.shape[::-1], good.points.dtype)),
         r"out: points must be a C-ordered array of shape"),
    ]
    shared = good.points.copy()
    cases.append((out(points=shared, d1=shared), r"out: d1 shares its memory"))
    for given, message in cases:
        before = [None if a is None else a.copy() for a in (given.points, given.d1)]
        with pytest.raises(ValueError, match=message):
            ctx.tessellate(curves, per_segment=5, derivatives=1, out=given)
        if message != r"out: d1 shares its memory":
            np.testing.assert_array_equal(given.points, before[0])


def test_arguments_are_refused_in_words_that_name_them(cpu):
    # Each raised an exception that named nothing (OverflowError, AxisError, numpy's reshape
    # or parse messages, pyo3's extraction errors) or was misread (a string parsed as a number).
    curve = np.random.default_rng(12).uniform(-1, 1, (6, 2))
    good = cpu.tessellate([curve], per_segment=3)
    cases = [
        (lambda: cpu.tessellate([curve], derivatives=-1), ValueError, "derivatives: must be"),
        (lambda: cpu.tessellate([curve], per_segment=float("nan")), ValueError,
         "per_segment: must be an integer"),
        (lambda: cpu.tessellate([curve], at="0.5"), TypeError, "at: must be numbers"),
        (lambda: cpu.tessellate([curve], "matrix", matrix=np.eye(3)), ValueError,
         r"matrix: must be 4 rows of 4 numbers, got shape \(3, 3\)"),
        (lambda: cpu.tessellate([[[0, 0], [1, 1, 1], [2, 0], [3, 1]]]), ValueError,
         r'curve 0: "points"'),
        (lambda: cpu.tessellate([curve], per_segment=3, out=splinegpu.Tessellation(
            good.t, good.points, None, None, good.curve_offsets.astype(np.int32))),
         ValueError, "out: curve_offsets must be a 1-D int64 array"),
    ]
    x = np.linspace(0, 1, 12)
    cases += [
        (lambda: splinegpu.CubicSpline(x, np.sin(x))(0.5, nu=-1), ValueError, "nu: must be"),
        (lambda: splinegpu.CubicSpline([], []), ValueError, "x: must contain at least 2"),
        (lambda: splinegpu.CubicSpline(x, np.float64(1.0)), ValueError, "y: must be at least 1-D"),
        (lambda: splinegpu.CubicSpline(x, np.zeros((3, 12)), axis=2), ValueError, "axis: must be"),
        (lambda: splinegpu.CubicSplines([x, x], [np.zeros((12, 2)), np.zeros((12, 3))]),
         ValueError, r"ys\[1\]: every spline's values must have the shape"),
    ]
    for call, error, message in cases:
        with pytest.raises(error, match=message):
            call()


def test_negative_axes_mean_what_they_mean_in_scipy():
    scipy_interpolate = pytest.importorskip("scipy.interpolate")
    x = np.linspace(0, 3, 12)
    y = np.random.default_rng(13).uniform(-1, 1, (3, 12))
    xq = np.random.default_rng(14).uniform(0, 3, (2, 3))
    for axis in (-1, 1):
        ours = splinegpu.CubicSpline(x, y, axis=axis)
        theirs = scipy_interpolate.CubicSpline(x, y, axis=axis)
        assert ours.axis == theirs.axis == 1
        assert ours(xq).shape == theirs(xq).shape == (3, 2, 3)
        np.testing.assert_allclose(ours(xq), theirs(xq), rtol=1e-12, atol=1e-12)
    y3 = np.random.default_rng(15).uniform(-1, 1, (2, 12, 4))
    ours, theirs = (splinegpu.CubicSpline(x, y3, axis=-2),
                    scipy_interpolate.CubicSpline(x, y3, axis=-2))
    assert ours.axis == theirs.axis == 1
    np.testing.assert_allclose(ours(xq), theirs(xq), rtol=1e-12, atol=1e-12)


def test_a_list_of_views_of_one_array_is_the_array(cpu):
    # list(arr) is how many callers hand over a batch; it is stacked into one array once
    # (it was quadratic: each view's borrow checked every other). Same result as the array.
    arr = np.random.default_rng(16).uniform(-1, 1, (300, 8, 3))
    whole = cpu.tessellate(arr, "bspline", per_segment=4, derivatives=1)
    views = cpu.tessellate(list(arr), "bspline", per_segment=4, derivatives=1)
    for a, b in zip((whole.t, whole.points, whole.d1, whole.curve_offsets),
                    (views.t, views.points, views.d1, views.curve_offsets)):
        np.testing.assert_array_equal(a, b)
    xs = np.sort(np.random.default_rng(17).uniform(0, 10, (50, 9)), axis=1)
    ys = np.random.default_rng(18).uniform(-1, 1, (50, 9, 2))
    xq = np.random.default_rng(19).uniform(0, 10, (50, 4)).clip(xs[:, :1], xs[:, -1:])
    together = splinegpu.CubicSplines(xs, ys)(xq)
    apart = splinegpu.CubicSplines(list(xs), list(ys))(list(xq))
    np.testing.assert_array_equal(together[0], apart[0])
    np.testing.assert_array_equal(together[1], apart[1])


def test_beta_bias_and_tension_per_joint(cpu):
    rng = np.random.default_rng(10)
    curves = rng.uniform(-1, 1, (4, 7, 3))
    for ends, joints in (("control", 5), ("repeat", 7), ("closed", 7)):
        # Equal values at every joint are the memo's Beta-spline, in every array form.
        memo = cpu.tessellate(curves, "beta", ends=ends, bias=1.4, tension=2.0, per_segment=5)
        for bias in (np.full(joints, 1.4), np.full((4, joints), 1.4), [np.full(joints, 1.4)] * 4):
            r = cpu.tessellate(curves, "beta", ends=ends, bias=bias, tension=2.0, per_segment=5)
            np.testing.assert_allclose(r.points, memo.points, rtol=0, atol=1e-12)
        # Each curve its own joints: curve i equals itself tessellated alone.
        bias = rng.uniform(0.2, 4, (4, joints))
        tension = rng.uniform(0, 5, (4, joints))
        together = cpu.tessellate(curves, "beta", ends=ends, bias=bias, tension=tension,
                                  derivatives=2, tolerance=1e-3)
        for i in range(4):
            alone = cpu.tessellate(curves[i:i + 1], "beta", ends=ends, bias=bias[i],
                                   tension=tension[i], derivatives=2, tolerance=1e-3)
            rows = slice(together.curve_offsets[i], together.curve_offsets[i + 1])
            np.testing.assert_array_equal(together.points[rows], alone.points)
            np.testing.assert_array_equal(together.d2[rows], alone.d2)
    with pytest.raises(ValueError, match=r'curve 2: "bias" must be > 0 at every joint: bias\[3\]'):
        bad = np.ones((4, 5))
        bad[2, 3] = -1.0
        cpu.tessellate(curves, "beta", bias=bad)
    with pytest.raises(ValueError, match=r'"tension" must have one value per joint \(7\), got 5'):
        cpu.tessellate(curves, "beta", ends="closed", tension=np.zeros(5))


def test_kochanek_bartels_keywords(cpu):
    rng = np.random.default_rng(9)
    curves = rng.uniform(-1, 1, (3, 6, 2))
    for ends in ("control", "repeat", "closed"):
        zero = cpu.tessellate(curves, "kochanek-bartels", ends=ends, per_segment=7)
        catmull = cpu.tessellate(curves, "catmull-rom", ends=ends, per_segment=7)
        np.testing.assert_allclose(zero.points, catmull.points, rtol=0, atol=1e-13)
        cardinal = cpu.tessellate(curves, "cardinal", ends=ends, tension=0.3, per_segment=7)
        # Tension T gives the cardinal spline of tension (1 - T) / 2, as a number or per point.
        for tension in (0.4, np.full(6, 0.4), np.full((3, 6), 0.4), [np.full(6, 0.4)] * 3):
            r = cpu.tessellate(curves, "kochanek-bartels", ends=ends, tension=tension,
                               per_segment=7)
            np.testing.assert_allclose(r.points, cardinal.points, rtol=0, atol=1e-13)
    # Per-point continuity and bias, and keys (n + 1 for closed ends), reach the curve.
    keys = np.cumsum(rng.uniform(0.1, 2, 7))
    r = cpu.tessellate(curves, "kochanek-bartels", ends="closed", continuity=np.linspace(-1, 1, 6),
                       bias=0.3, t=keys, per_segment=4)
    assert r.t[0] == keys[0] and r.t[-1] == keys[-1]
    with pytest.raises(ValueError, match=r'curve 0: "continuity" must have one value per point'):
        cpu.tessellate(curves, "kochanek-bartels", continuity=np.zeros(5))
    with pytest.raises(ValueError, match=r'"tension" must be a number for a "cardinal" curve'):
        cpu.tessellate(curves, "cardinal", tension=np.zeros(6))
    with pytest.raises(TypeError, match="bias"):
        cpu.tessellate(curves, "kochanek-bartels", bias=True)
