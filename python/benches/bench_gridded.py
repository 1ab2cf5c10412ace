"""The gridded rows of `python python/benches/bench.py` (`--gridded` runs them alone): each the
whole call as a caller makes it (construction included where the row says so), against SciPy in
the same run on the same inputs, and on the GPU backend where a surface carries the work.

Grids are evenly spaced (as xarray's coordinates) but for the ragged ones (each node moved by
up to 0.3 of the step): SciPy's iterative solve converges slowly on uneven grids (minutes for
the first case on sorted uniform draws) or not at all (gcrotmk's info = 1000 on several of the
ragged grids drawn that way), where the separable direct fit is exact.

- xarray#11342's case: RegularGridInterpolator "cubic" on a 288 x 71 x 73 grid, built and
  called at one point, with the extra memory it takes (the peak resident set it adds, each in a
  fresh interpreter);
- RegularGridInterpolator on a 256 x 256 grid at 1,000,000 random points, built and called:
  "cubic" and "linear"; "pchip" at 10,000 points (SciPy's recursive fold costs ~0.3 ms a point);
- NdBSpline calls at 1,000,000 points, bicubic (2-D, 22 x 22) and tricubic (3-D, 22^3);
- 1,000 ragged 2-D grids of 32 to 128 points per axis, each at its own 1,000 points, built and
  called: RegularGridInterpolators "linear" against SciPy's loop, and "cubic" against SciPy's
  loop over the first 100 grids, scaled by 10 (SciPy's iterative construction takes ~0.1 s a
  grid: the whole loop would take minutes).
"""

from __future__ import annotations

import sys
import time

import numpy as np
from timing import Rows, best, faster

# The extra memory of the xarray#11342 call, measured in a fresh interpreter: its peak
# resident set over the one it had with the grid made (tracemalloc would slow SciPy's
# Python-level iterative solve a hundredfold). Linux's /proc.
_MEMORY = """
import numpy as np
import {module} as m


def high_water():
    # VmHWM: this process' peak resident set (ru_maxrss would carry the parent's over exec).
    with open("/proc/self/status") as status:
        line = next(l for l in status if l.startswith("VmHWM:"))
    return int(line.split()[1]) * 1024


rng = np.random.default_rng(31)
axes = tuple(np.linspace(0, 1, n) for n in (288, 71, 73))
values = rng.normal(size=(288, 71, 73))
point = np.stack([rng.uniform(a[0], a[-1], 1) for a in axes], axis=-1)
before = high_water()
m.RegularGridInterpolator(axes, values, method="cubic")(point)
print(high_water() - before)
"""


def _extra_memory(module: str) -> float:
    """Bytes the xarray#11342 call adds to the peak resident set, in its own interpreter."""
    import subprocess

    done = subprocess.run([sys.executable, "-c", _MEMORY.format(module=module)],
                          capture_output=True, text=True, check=True)
    return float(done.stdout.split()[-1])


def _grid(rng, shape, uneven=False):
    """Axes on [0, 1] (evenly spaced, as xarray's coordinates; or `uneven`, each node moved
    by up to 0.3 of the step) and normal values on them."""
    axes = tuple(np.linspace(0, 1, n) + (rng.uniform(-0.3, 0.3, n) / n if uneven else 0.0)
                 for n in shape)
    return axes, rng.normal(size=shape)


def _inside(rng, axes, count):
    return np.stack([rng.uniform(a[0], a[-1], count) for a in axes], axis=-1)



def rows(gpu) -> list:
    import scipy.interpolate as scipy

    import splinegpu.interpolate as si

    rng = np.random.default_rng(31)
    out = Rows()
    adapter = gpu.info.removeprefix("gpu: ").split(" (")[0] if gpu is not None else None

    axes, values = _grid(rng, (288, 71, 73))
    point = _inside(rng, axes, 1)
    a = best(lambda: si.RegularGridInterpolator(axes, values, method="cubic")(point))
    b = best(lambda: scipy.RegularGridInterpolator(axes, values, method="cubic")(point),
             repeats=1)
    out.append(("RGI cubic 288x71x73, make + 1 point", a, "SciPy (1 run)", b,
                faster(a, b, ">= 20x")))
    mine, scipys = _extra_memory("splinegpu.interpolate"), _extra_memory("scipy.interpolate")
    out.append(("  extra memory (peak RSS), MB", mine / 1e6, "SciPy", scipys / 1e6,
                "(goal < 100 MB)"))

    axes, values = _grid(rng, (256, 256))
    points = _inside(rng, axes, 1_000_000)
    for method, count, goal in (("cubic", 1_000_000, ">= 10x"), ("linear", 1_000_000, None),
                                ("pchip", 10_000, None)):
        xi = points[:count]
        a = best(lambda m=method, xi=xi: si.RegularGridInterpolator(axes, values, method=m)(xi))
        b = best(lambda m=method, xi=xi: scipy.RegularGridInterpolator(axes, values,
                                                                       method=m)(xi), repeats=1)
        label = f"{count:,}".replace(",000,000", " M").replace(",000", "k")
        out.append((f"RGI {method} 256x256, make + {label} pts", a, "SciPy (1 run)", b,
                    faster(a, b, goal)))
        if gpu is not None and method == "cubic":
            g = best(lambda xi=xi: si.RegularGridInterpolator(axes, values, method="cubic",
                                                              context=gpu)(xi), repeats=2)
            out.append((f"  the same on the GPU backend ({adapter})", g, "CPU backend", a,
                        faster(g, a)))

    for d, n in ((2, 22), (3, 22)):
        t = tuple(np.r_[[0.0] * 4, np.sort(rng.uniform(0, 1, n - 4)), [1.0] * 4]
                  for _ in range(d))
        c = rng.normal(size=(n,) * d)
        xi = rng.uniform(0, 1, (1_000_000, d))
        ours, theirs = si.NdBSpline(t, c, 3), scipy.NdBSpline(t, c, 3)
        a, b = best(lambda ours=ours, xi=xi: ours(xi)), best(lambda th=theirs, xi=xi: th(xi))
        out.append((f"NdBSpline {d}-D cubic call, 1 M pts", a, "SciPy", b, faster(a, b, ">= 5x")))
        if gpu is not None and d == 2:
            on_gpu = si.NdBSpline(t, c, 3, context=gpu)
            g = best(lambda s=on_gpu, xi=xi: s(xi), repeats=2)
            out.append((f"  the same on the GPU backend ({adapter})", g, "CPU backend", a,
                        faster(g, a)))

    grids, tables, xis = [], [], []
    for _ in range(1000):
        g, v = _grid(rng, tuple(int(n) for n in rng.integers(32, 129, 2)), uneven=True)
        grids.append(g)
        tables.append(v)
        xis.append(_inside(rng, g, 1000))
    for method, sample in (("linear", 1000), ("cubic", 100)):
        a = best(lambda m=method: si.RegularGridInterpolators(grids, tables, method=m)(xis))
        start = time.perf_counter()
        for g, v, xi in zip(grids[:sample], tables[:sample], xis[:sample]):
            scipy.RegularGridInterpolator(g, v, method=method)(xi)
        b = (time.perf_counter() - start) * (1000 / sample)
        against = "SciPy loop (1 run)" if sample == 1000 else "SciPy loop, 100 x 10"
        out.append((f"RGIs {method}, 1,000 ragged grids", a, against, b, faster(a, b, ">= 20x")))
        if gpu is not None and method == "cubic":
            g = best(lambda: si.RegularGridInterpolators(grids, tables, method="cubic",
                                                         context=gpu)(xis), repeats=2)
            out.append((f"  the same on the GPU backend ({adapter})", g, "CPU backend", a,
                        faster(g, a)))
    return out
