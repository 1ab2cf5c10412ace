"""Cubic splines fitted in float64 and evaluated in bulk on the GPU or on every CPU thread.

    >>> import numpy as np, splinegpu
    >>> ctx = splinegpu.Context("cpu")
    >>> curves = np.random.default_rng(0).uniform(-1, 1, (100, 10, 3))
    >>> r = ctx.tessellate(curves, kind="catmull-rom", per_segment=16)
    >>> r.points.shape, r.curve_offsets[:3]
    ((11300, 3), array([  0, 113, 226]))

The curve kinds, their fields and the four samplings are those of the `splinegpu` command line
(docs/input-format.md in the repository); results hold the same numbers as its NPZ output: float32
from the GPU backend, float64 from the CPU backend, t always float64.

`CubicSpline` follows `scipy.interpolate.CubicSpline` for the cases it covers.
"""

from __future__ import annotations

import os

# Mesa's device-select Vulkan layer prints XDG_RUNTIME_DIR warnings on headless machines unless
# this is set before the first Vulkan instance exists (as the command line does).
os.environ.setdefault("NODEVICE_SELECT", "1")

from . import _native
from ._context import Context, Tessellation
from ._geometry import Meshes
from ._queries import ClosestPoints, Intersections, RayHits, SurfacePoints
from ._surfaces import SurfaceTessellation
from .interpolate import CubicSpline, CubicSplines

__all__ = ["KIND_NAMES", "ClosestPoints", "Context", "CubicSpline", "CubicSplines",
           "Intersections", "Meshes", "RayHits", "SurfacePoints",
           "SurfaceTessellation", "Tessellation"]

KIND_NAMES: tuple = tuple(_native.KIND_NAMES)
