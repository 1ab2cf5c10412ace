"""SciPy's 1-D splines (`scipy.interpolate`'s names and signatures), fitted in float64 on the
host and evaluated through a `Context`, and batches of many: `import
splinegpu.interpolate as si` runs SciPy code unchanged where it is covered (python/README.md
has the table of what is and how it differs).

    >>> import numpy as np, splinegpu.interpolate as si
    >>> x = np.linspace(0, 10, 11)
    >>> s = si.PchipInterpolator(x, np.sqrt(x))
    >>> float(s(2.5))  # doctest: +ELLIPSIS
    1.57...
"""

from __future__ import annotations

from ._batches import (
    Akima1DInterpolators,
    BSplines,
    CubicHermiteSplines,
    CubicSplines,
    NdBSplines,
    PchipInterpolators,
    PPolys,
    RegularGridInterpolators,
    make_interp_splines,
    make_lsq_splines,
    make_smoothing_splines,
    make_splpreps,
    make_splreps,
)
from ._bpoly import BPoly
from ._bsplines import BSpline, make_interp_spline
from ._cubic import (
    Akima1DInterpolator,
    CubicHermiteSpline,
    CubicSpline,
    PchipInterpolator,
    pchip_interpolate,
)
from ._fitpack2 import (
    InterpolatedUnivariateSpline,
    LSQUnivariateSpline,
    RectBivariateSpline,
    UnivariateSpline,
)
from ._fitpack_py import insert, splantider, splder, splev, splint, splprep, splrep, sproot
from ._fitpack_repro import make_splprep, make_splrep
from ._interp1d import interp1d
from ._lsq import make_lsq_spline
from ._ndbspline import NdBSpline
from ._ppoly import PPoly
from ._rgi import RegularGridInterpolator, interpn
from ._smoothing import make_smoothing_spline

# SciPy's alias of PchipInterpolator.
pchip = PchipInterpolator

__all__ = ["Akima1DInterpolator", "Akima1DInterpolators", "BPoly", "BSpline", "BSplines",
           "CubicHermiteSpline", "CubicHermiteSplines", "CubicSpline", "CubicSplines",
           "InterpolatedUnivariateSpline", "LSQUnivariateSpline", "NdBSpline", "NdBSplines",
           "PPoly", "PPolys", "PchipInterpolator", "PchipInterpolators", "RectBivariateSpline",
           "RegularGridInterpolator", "RegularGridInterpolators", "UnivariateSpline",
           "insert", "interp1d", "interpn", "make_interp_spline", "make_interp_splines",
           "make_lsq_spline", "make_lsq_splines", "make_smoothing_spline", "make_smoothing_splines",
           "make_splprep", "make_splpreps", "make_splrep", "make_splreps", "pchip",
           "pchip_interpolate", "splantider", "splder", "splev", "splint", "splprep", "splrep",
           "sproot"]
