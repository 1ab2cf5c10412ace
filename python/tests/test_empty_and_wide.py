"""Every 1-D class of splinegpu.interpolate on y of no values per x (zero-size axes, as
SciPy takes them) and of more than the crate's 64 values per x (fitted and evaluated in
blocks of columns), against SciPy 1.17: the same shapes, values within 1e-12 of the largest;
and a fit whose slopes overflow float64 refused as SciPy refuses it."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import interpolate

import splinegpu.interpolate as si

CLASSES = {
    "CubicSpline": lambda m, x, y, axis: m.CubicSpline(x, y, axis=axis),
    "CubicSpline natural": lambda m, x, y, axis: m.CubicSpline(x, y, axis=axis,
                                                               bc_type="natural"),
    "CubicHermiteSpline": lambda m, x, y, axis: m.CubicHermiteSpline(x, y, np.cos(y), axis=axis),
    "PchipInterpolator": lambda m, x, y, axis: m.PchipInterpolator(x, y, axis=axis),
    "Akima1DInterpolator": lambda m, x, y, axis: m.Akima1DInterpolator(x, y, axis=axis,
                                                                       extrapolate=True),
    "make_interp_spline": lambda m, x, y, axis: m.make_interp_spline(x, y, axis=axis),
    "make_interp_spline k=5": lambda m, x, y, axis: m.make_interp_spline(x, y, k=5, axis=axis),
}


@settings(max_examples=40, deadline=None)
@given(st.sampled_from(sorted(CLASSES)), st.integers(0, 2**32 - 1),
       st.sampled_from([(0,), (0, 3), (2, 0), (70,), (3, 45), (130,)]), st.integers(0, 2))
def test_empty_and_wide_values_are_scipys(name, seed, trailing, axis):
    rng = np.random.default_rng(seed)
    x = np.cumsum(rng.uniform(0.1, 2.0, 9))
    y = rng.normal(size=(len(x), *trailing))
    axis = min(axis, len(trailing))
    y = np.moveaxis(y, 0, axis)
    make = CLASSES[name]
    ours, theirs = make(si, x, y, axis), make(interpolate, x, y, axis)
    q = np.concatenate([x, rng.uniform(x[0] - 1, x[-1] + 1, 7)]).reshape(4, 4)
    for nu in (0, 1):
        got, want = ours(q, nu), theirs(q, nu)
        assert got.shape == want.shape
        if want.size:
            scale = max(1.0, float(np.max(np.abs(want))))
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-12 * scale)


def test_a_bspline_of_336_values_per_coefficient_is_scipys():
    rng = np.random.default_rng(5)
    t = np.r_[[0.0] * 3, np.linspace(0, 1, 9), [1.0] * 3]
    c = rng.normal(size=(len(t) - 4, 8, 42))
    q = rng.uniform(0, 1, 50)
    ours, theirs = si.BSpline(t, c, 3), interpolate.BSpline(t, c, 3)
    np.testing.assert_allclose(ours(q), theirs(q), rtol=0, atol=1e-12 * np.abs(c).max())
    np.testing.assert_allclose(ours.integrate(0.1, 0.9), theirs.integrate(0.1, 0.9),
                               rtol=0, atol=1e-12 * np.abs(c).max())


def test_slopes_past_float64_are_refused_as_scipy_refuses_them():
    with pytest.raises(ValueError), np.errstate(over="ignore"):
        interpolate.CubicSpline([0, 1e-300, 1, 2], [0, 1e300, 0, 1])
    with pytest.raises(ValueError, match="slopes are not finite"):
        si.CubicSpline([0, 1e-300, 1, 2], [0, 1e300, 0, 1])
    with pytest.raises(ValueError, match="slopes are not finite"):
        si.PchipInterpolator([0, 1e-300, 1, 2], [0, 1e300, 0, 1])


_UNDER_A_LIMIT = """
import resource, numpy as np
import splinegpu.interpolate as si
x = np.linspace(0, 1, 10)
f = si.interp1d(x, np.sin(x), kind="cubic")
at = np.linspace(0, 1, 50_000_000)  # 400 MB
size = int(open("/proc/self/status").read().split("VmSize:")[1].split()[0]) * 1024
resource.setrlimit(resource.RLIMIT_AS, (size + 200_000_000, resource.RLIM_INFINITY))
try:
    f(at)  # another 400 MB of values: past the limit
except MemoryError as e:
    print("MemoryError", e)
"""


def test_a_result_past_the_process_limit_is_a_memory_error_not_an_abort(tmp_path):
    """Under an address-space limit (RLIMIT_AS, set in a child process of its own) that the
    memory estimate does not see, the result's allocation fails as a MemoryError (it aborted
    the interpreter with "memory allocation of ... bytes failed" before)."""
    import subprocess
    import sys

    # From a folder of its own, so that the child imports the installed package.
    done = subprocess.run([sys.executable, "-c", _UNDER_A_LIMIT], capture_output=True,
                          text=True, timeout=120, cwd=tmp_path)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.startswith("MemoryError"), (done.stdout, done.stderr[-2000:])
