"""`Context` (where splines are evaluated) and `Tessellation` (what `Context.tessellate`
returns), and the shared CPU context that calls without a context use."""

from __future__ import annotations

import threading

import numpy as np

from . import _native
from ._geometry import Meshes, meshes
from ._helpers import _curve_fields, _curve_sampling, _curves, _order
from ._queries import (
    ClosestPoints,
    Intersections,
    RayHits,
    SurfacePoints,
    closest,
    closest_on_surfaces,
    first_hits,
    intersections,
)
from ._surfaces import tessellate_surfaces


class Tessellation:
    """The samples of a `Context.tessellate` call.

    Attributes: `t` (N,) float64; `points` (N, D); `d1`, `d2` (N, D) or None when not asked
    for; `curve_offsets` (C + 1,) int64: curve c owns rows curve_offsets[c]:curve_offsets[c+1].
    """

    __slots__ = ("curve_offsets", "d1", "d2", "points", "t")

    def __init__(self, t, points, d1, d2, curve_offsets):
        self.t = t
        self.points = points
        self.d1 = d1
        self.d2 = d2
        self.curve_offsets = curve_offsets

    def curve(self, c: int) -> Tessellation:
        """Curve c's rows (views, no copy)."""
        a, b = self.curve_offsets[c], self.curve_offsets[c + 1]
        pick = lambda x: None if x is None else x[a:b]  # noqa: E731
        return Tessellation(self.t[a:b], self.points[a:b], pick(self.d1), pick(self.d2),
                            np.array([0, b - a], dtype=np.int64))

    def __len__(self) -> int:
        return len(self.t)

    def __repr__(self) -> str:
        return (f"Tessellation({len(self.curve_offsets) - 1} curves, {len(self.t)} samples, "
                f"points {self.points.dtype} {self.points.shape})")


class Context:
    """Where splines are evaluated: made once and reused (threads may share it).

    `backend`: "auto" (a hardware GPU when there is one, else the CPU), "gpu" (any adapter,
    lavapipe included; RuntimeError without one) or "cpu" (float64 on every thread).
    """

    def __init__(self, backend: str = "auto"):
        self._native = _native.Context(backend)
        self._requested = backend

    def __reduce__(self):
        # A context pickles as the backend asked for, and opens it again where it is unpickled
        # (a Dask worker, a process pool): an adapter cannot travel.
        return (Context, (self._requested,))

    @property
    def info(self) -> str:
        """The adapter (or the CPU) this context evaluates on."""
        return self._native.info

    @property
    def backend(self) -> str:
        """"gpu" or "cpu"."""
        return self._native.backend

    def __repr__(self) -> str:
        return f"splinegpu.Context({self.info!r})"

    def tessellate(self, points, kind: str = "catmull-rom", *, ends: str | None = None,
                   tension=None, bias=None, continuity=None,
                   matrix=None, t=None, start_derivative=None, end_derivative=None,
                   tangents=None, method: str | None = None, knots=None, weights=None,
                   per_segment: int | None = None, at=None, arc_length: int | None = None,
                   tolerance: float | None = None, derivatives: int = 0,
                   out: Tessellation | None = None) -> Tessellation:
        """Fits and samples a batch of curves of one kind.

        `points`: a (C, n, D) array or a list of (n_i, D) arrays (ragged). `kind` and its fields
        are the command line's (KIND_NAMES); `t`, `at` and the clamped derivatives are one array
        for every curve, a 2-D array with a row per curve, or a list (ragged); hermite's
        `tangents` are an (n, D) array for every curve, a (C, n, D) array or a list of (n_i, D)
        arrays; akima's `method` is "akima" or "makima"; kochanek-bartels' `tension`,
        `continuity` and `bias` are numbers, or per point: an (n,) array for every curve, a
        (C, n) array or a list of arrays; beta's `bias` and `tension` likewise, numbers or one
        value per joint (n - 2 with "control" ends, n with "repeat" and "closed": Barsky and
        Beatty's local bias and tension); nurbs' `knots` (n + 4 per curve) likewise. One sampling:
        `per_segment=k` (the default, 16), `at=t values`, `arc_length=m` or `tolerance=tol`
        (arc-length samples within 1e-10 of the length on the CPU; the GPU places them itself,
        within 1e-5, so their t differ between backends in the low bits; tolerance t are the
        same on both). `derivatives`: 0, 1 or 2 (d/dt). `out`: an earlier result of the same
        shape, whose arrays are filled again instead of new ones.

        Raises ValueError naming the curve, field and value for bad input.
        """
        curves = _curves(points)
        sampling = _curve_sampling(len(curves), per_segment=per_segment, at=at,
                                   arc_length=arc_length, tolerance=tolerance)
        fields = _curve_fields(len(curves), ends=ends, tension=tension, bias=bias,
                               continuity=continuity, matrix=matrix, t=t,
                               start_derivative=start_derivative,
                               end_derivative=end_derivative, tangents=tangents, method=method,
                               knots=knots, weights=weights)
        derivatives = _order("derivatives", derivatives, 2)
        reuse = None
        if out is not None:
            for array, what, dtype in ((out.t, "t", np.float64),
                                       (out.curve_offsets, "curve_offsets", np.int64)):
                if not isinstance(array, np.ndarray) or array.dtype != dtype or array.ndim != 1:
                    raise ValueError(f"out: {what} must be a 1-D {np.dtype(dtype)} array, got "
                                     f"{getattr(array, 'dtype', type(array).__name__)}")
            reuse = (out.t, out.points, out.d1, out.d2, out.curve_offsets)
        result = self._native.tessellate(curves, kind, fields, sampling, derivatives, reuse)
        return Tessellation(*result)

    def strokes(self, points, kind: str = "catmull-rom", *, width, cap: str = "butt",
                join: str = "miter", miter_limit: float = 4.0, sides: int = 16, dash=None,
                dash_offset: float | None = None, per_segment: int | None = None, at=None,
                arc_length: int | None = None, tolerance: float | None = None,
                out: Meshes | None = None, **fields) -> Meshes:
        """Strokes of a batch of 2-D curves of one kind: the area a pen of width w(t) sweeps
        along each curve, with joins at its corners and caps at its ends, as triangles.

        `points` and `kind` as `tessellate` takes them, and the kind's fields (`ends=`,
        `tension=`, `t=`, `knots=`, ...) as keywords. `width`: a number, or one value per point
        (an (n,) array for every curve, a (C, n) array or a list), interpolated as one more
        coordinate of the same spline. `cap`: "butt", "round" or "square"; `join`: "miter",
        "round" or "bevel", a miter beyond `miter_limit` (1 / sin(φ/2), φ the interior angle)
        drawn as a bevel; `sides`: chords per full turn of round joins and caps (>= 4). `dash`:
        on and off lengths by arc length (an even count, >= 0, a sum > 0), `dash_offset` how
        far into the pattern each curve starts; each dash is an open stroke with its caps.
        Cross-sections: `per_segment=k` (default 16), `arc_length=m` or `tolerance=tol` (the
        mesh certified within tol of the exact area: every triangle within tol of it, every
        point of it farther than tol from its edge covered; round joins and caps then take
        the fewest chords within tol, `sides` aside); a corner always gets its join. Tolerance
        needs a curve whose speed does not vanish (ValueError naming "tolerance" and the t
        otherwise). Meshes are made on
        the context's backend: float64 on the CPU; on the GPU tubes and ribbons in float32,
        strokes on the host rounded to float32. `out`: an earlier result of
        the same shapes, whose arrays are filled again.

        Raises ValueError naming the curve, field and value for bad input.
        """
        return meshes(self, "stroke", points, kind, width=width, width_name="width", cap=cap,
                      join=join, miter_limit=miter_limit, sides=sides, dash=dash,
                      dash_offset=dash_offset, per_segment=per_segment, at=at,
                      arc_length=arc_length, tolerance=tolerance, out=out, fields=fields)

    def tubes(self, points, kind: str = "catmull-rom", *, radius, sides: int | None = None,
              up=None,
              caps: bool = False, dash=None, dash_offset: float | None = None,
              per_segment: int | None = None, at=None, arc_length: int | None = None,
              tolerance: float | None = None, out: Meshes | None = None, **fields) -> Meshes:
        """Tubes about a batch of 3-D curves of one kind: rings of `sides` vertices at radius
        r(t) about each curve, in its rotation-minimizing frames (closed up on closed curves),
        with the exact surface's unit normals.

        `sides`: vertices per ring (>= 3); by default 8, or with `tolerance=tol` the method's
        choice (half of tol to the rings' polygons at the largest radius). With tolerance the
        mesh and the exact tube are within tol of each other both ways (ribbons likewise), on
        curves whose tangent is continuous and whose speed does not vanish (ValueError naming
        "tolerance" and the t otherwise); given sides whose polygon alone strays more than tol
        are refused naming "sides".

        `radius`: a number or one value per point, as `strokes`' width. `up`: 3 numbers, the
        first frame's normal before it is made perpendicular to the first tangent (default:
        the axis least aligned with it). `caps`: discs closing an open tube's ends. `dash`,
        `dash_offset`, the sampling, `out` and the kind's fields as for `strokes`; a dashed
        tube's frames are carried through its gaps, not restarted.

        Raises ValueError naming the curve, field and value for bad input.
        """
        return meshes(self, "tube", points, kind, width=radius, width_name="radius",
                      sides=sides, up=up, caps=caps, dash=dash, dash_offset=dash_offset,
                      per_segment=per_segment, at=at, arc_length=arc_length,
                      tolerance=tolerance, out=out, fields=fields)

    def ribbons(self, points, kind: str = "catmull-rom", *, width, up=None, dash=None,
                dash_offset: float | None = None, per_segment: int | None = None, at=None,
                arc_length: int | None = None, tolerance: float | None = None,
                out: Meshes | None = None, **fields) -> Meshes:
        """Ribbons along a batch of 3-D curves of one kind: the strip C(t) + s B(t), |s| <=
        w(t)/2, facing the rotation-minimizing normal N(t), which is each vertex's normal.
        `width`, `up`, `dash`, `dash_offset`, the sampling, `out` and the kind's fields as for
        `tubes`.

        Raises ValueError naming the curve, field and value for bad input.
        """
        return meshes(self, "ribbon", points, kind, width=width, width_name="width", up=up,
                      dash=dash, dash_offset=dash_offset, per_segment=per_segment, at=at,
                      arc_length=arc_length, tolerance=tolerance, out=out, fields=fields)

    def closest(self, curves, kind: str = "catmull-rom", points=None, **fields) -> ClosestPoints:
        """The closest point of a batch of curves of one kind to each query point, certified:
        for every row of `points` ((Q, D), or one point as (D,)), the nearest curve, its
        parameter t, the point C(t) and its distance, within 1e-9 (E + |q|) of the true least
        distance over every curve and every t (E the curves' extent; no local minimum in place
        of the global one; among ties within that, any).

        `curves` and `kind` as `tessellate` takes its `points` and `kind`, the kind's fields
        (`ends=`, `t=`, `knots=`, `weights=`, ...) as keywords. Answered on the context's
        backend: on the CPU in float64 on every thread (a box tree over the segments, an exact
        solve on each segment it cannot exclude); on a GPU one query per invocation in float32
        (point and distance float32, t float64), within the curve's f32 position bound plus
        1e-5 (E + |q|) of the least distance.

        Raises ValueError naming the curve, field and value, or the query, for bad input.
        """
        if points is None:
            raise TypeError("closest: missing the query points (points=)")
        return closest(curves, kind, points, fields, self._native)

    def intersections(self, curves, kind: str = "catmull-rom", pairs="all",
                      **fields) -> Intersections:
        """Every point where two 2-D curves of a batch meet, certified: each isolated meeting
        point lies within 1e-9 (E + |q|) of a reported one, each reported one is a meeting
        within that, a crossing is reported once (also at a joint); touching points are
        flagged `tangent`, and where two curves coincide along a piece its two ends are
        reported with `overlap` and nothing between them.

        `curves`, `kind` and the kind's fields as `closest` takes them. `pairs`: "all" (every
        i < j) or (K, 2) curve indices, [i, i] asking for curve i's self-intersections (pairs
        t_i < t_j; never a joint with itself, nor a closed curve's start with its end).
        Answered on every CPU thread in float64 on every context.

        Raises ValueError naming the curve, field and value, or the pair, for bad input.
        """
        return intersections(curves, kind, pairs, fields)

    def closest_on_surfaces(self, nets, kind: str = "bspline", points=None,
                            **fields) -> SurfacePoints:
        """The closest point of a batch of surfaces of one kind to each query point, certified
        within 1e-9 (E + |q|) of the least distance over every surface and every (u, v) (no
        local minimum in place of the global one; among ties, any).

        `nets` and `kind` as `tessellate_surfaces` takes them, the kind's fields (`ends=`,
        `patches=`, `knots_u=`, `weights=`, ...) as keywords; `points` (Q, D) or one (D,).
        Answered on the context's backend: on a GPU each (u, v) found in float32 (point and
        distance float32, within the patch's f32 position bound plus 1e-5 (E + |q|)).

        Raises ValueError naming the surface, field and value, or the query, for bad input.
        """
        if points is None:
            raise TypeError("closest_on_surfaces: missing the query points (points=)")
        return closest_on_surfaces(nets, kind, points, fields, self._native)

    def rays(self, nets, kind: str = "bspline", rays=None, **fields) -> RayHits:
        """The first point where each ray o + s d, s >= 0, meets a batch of 3-D surfaces of
        one kind, certified: no point of any surface on the ray is nearer (in s) by more than
        1e-9 (E + |o|); none where it meets nothing within s <= 1e6 (E + |o|). A ray that
        starts on a surface meets it at s = 0.

        `nets`, `kind` and the kind's fields as `closest_on_surfaces`; `rays` (Q, 6) rows
        (ox, oy, oz, dx, dy, dz), or one (6,). Answered on the context's backend (on a GPU
        point and normal float32, u, v and s float64, within the GPU bound).

        Raises ValueError naming the surface, field and value, or the ray, for bad input.
        """
        if rays is None:
            raise TypeError("rays: missing the rays (rays=)")
        return first_hits(nets, kind, rays, fields, self._native)

    def tessellate_surfaces(self, nets, kind: str = "bspline", *, ends=None, tension=None,
                            bias=None, matrix=None, patches=None, conditions=None, u=None,
                            v=None, knots_u=None, knots_v=None, weights=None,
                            per_segment=None, at=None, tolerance=None, derivatives: int = 0,
                            normals: bool = False, out=None):
        """Fits, samples and evaluates a batch of surfaces of one kind: a
        `SurfaceTessellation` holding the arrays of the command line's NPZ.

        `nets`: an (n_u, n_v, D) array, a list of them (each its own shape) or an (S, n_u,
        n_v, D) array; with `patches` (bezier patch lists, the Utah teapot's form), a list of
        (n, D) control-point arrays and `patches` one (P, 16) integer array for all or a list
        of one per surface. `kind` and its fields are the contract's surface kinds ("bspline",
        "catmull-rom", "cardinal", "tensioned-bspline", "beta", "matrix" with `ends` (one
        name or (ends_u, ends_v)), `tension`, `bias`, `matrix`; "bezier"; "interpolating"
        with `conditions` (c_u, c_v) and optional `u`, `v`; "nurbs" with `knots_u`, `knots_v`
        and optional `weights`); `u`, `v`, `knots_u`, `knots_v` and `weights` are one array
        for all surfaces or a list with one per surface. One sampling: `per_segment=k` or
        (k_u, k_v) (the default, 16), `at=` (N, 2) parameter pairs ((N, 3) triples (p, u, v)
        on patch lists; one array for all or a list), or `tolerance=tol` (a certified,
        watertight mesh). `derivatives`: 0, 1 (du, dv) or 2 (and duu, duv, dvv); `normals`:
        unit normals (3-D surfaces). `out`: an earlier result of the same shapes, whose
        arrays are filled again instead of new ones.

        Raises ValueError naming the surface, field and value for bad input.
        """
        return tessellate_surfaces(self, nets, kind, ends=ends, tension=tension, bias=bias,
                                   matrix=matrix, patches=patches, conditions=conditions,
                                   u=u, v=v, knots_u=knots_u, knots_v=knots_v,
                                   weights=weights, per_segment=per_segment, at=at,
                                   tolerance=tolerance, derivatives=derivatives,
                                   normals=normals, out=out)


_shared_cpu: Context | None = None
_shared_lock = threading.Lock()


def default_context() -> Context:
    global _shared_cpu
    with _shared_lock:
        if _shared_cpu is None:
            _shared_cpu = Context("cpu")
        return _shared_cpu


def shared_context():
    """The native half of `self.context`'s default, made once (a call takes no lock after)."""
    return (_shared_cpu or default_context())._native
