"""Strokes, tubes and ribbons from Python: the command line's NPZ arrays for the same document
(every shape, dashes, per-point widths, kinds with fields), shapes against a hand derivation (a
straight tube's rings and radial normals, a straight stroke's offsets, a ribbon's width at its
points), batches ragged or stacked, `out=`, trimesh, and bad input named."""

from __future__ import annotations

import numpy as np
import pytest
from test_tessellate import cli_npz

RNG = np.random.default_rng(45)
LOOPS = RNG.uniform(-1, 1, (5, 7, 3))
PATHS = RNG.uniform(-1, 1, (4, 6, 2))


def document(points, kind, fields, geometry, sampling):
    curves = [{"kind": kind, "points": p.tolist(), **fields} for p in points]
    return {"sampling": dict([sampling]), "geometry": geometry, "curves": curves}


CASES = [
    # points, kind, kind fields, geometry (the document's), Python keywords, sampling
    (LOOPS, "catmull-rom", {"ends": "closed"}, {"tube": {"radius": 0.05, "sides": 6}},
     "tubes", {"radius": 0.05, "sides": 6}, ("per_segment", 5)),
    (LOOPS, "natural", {}, {"tube": {"radius": 0.05, "caps": True, "up": [0, 0, 1]}},
     "tubes", {"radius": 0.05, "caps": True, "up": [0, 0, 1]}, ("arc_length", 40)),
    (LOOPS, "bspline", {"ends": "repeat"},
     {"ribbon": {"width": [0.1, 0.2, 0.1, 0.3, 0.1, 0.2, 0.1], "dash": [0.4, 0.2]}},
     "ribbons", {"width": np.array([0.1, 0.2, 0.1, 0.3, 0.1, 0.2, 0.1]), "dash": [0.4, 0.2]},
     ("per_segment", 8)),
    (PATHS, "catmull-rom", {}, {"stroke": {"width": 0.1, "join": "round", "cap": "round"}},
     "strokes", {"width": 0.1, "join": "round", "cap": "round"}, ("per_segment", 6)),
    (PATHS, "cardinal", {"tension": 0.3},
     {"stroke": {"width": 0.08, "cap": "square", "miter_limit": 2, "dash": [0.3, 0.1, 0, 0.1],
                 "dash_offset": 0.05}},
     "strokes", {"width": 0.08, "cap": "square", "miter_limit": 2, "dash": [0.3, 0.1, 0, 0.1],
                 "dash_offset": 0.05}, ("arc_length", 30)),
    (LOOPS, "catmull-rom", {"ends": "closed"}, {"tube": {"radius": 0.05}},
     "tubes", {"radius": 0.05}, ("tolerance", 2e-3)),
    (LOOPS, "natural", {}, {"ribbon": {"width": 0.1, "dash": [0.4, 0.2]}},
     "ribbons", {"width": 0.1, "dash": [0.4, 0.2]}, ("tolerance", 1e-3)),
    (PATHS, "catmull-rom", {}, {"stroke": {"width": 0.1, "join": "round", "cap": "round"}},
     "strokes", {"width": 0.1, "join": "round", "cap": "round"}, ("tolerance", 1e-3)),
]


@pytest.mark.parametrize("points, kind, fields, geometry, method, keywords, sampling", CASES)
def test_meshes_equal_the_command_line(cpu, points, kind, fields, geometry, method, keywords,
                                       sampling):
    npz = cli_npz(document(points, kind, fields, geometry, sampling))
    result = getattr(cpu, method)(points, kind, **keywords, **fields,
                                  **{sampling[0]: sampling[1]})
    assert set(result.arrays()) == set(npz)
    for name, want in npz.items():
        got = getattr(result, name)
        assert got.dtype == want.dtype and got.shape == want.shape, name
        np.testing.assert_array_equal(got, want, err_msg=name)


def test_a_straight_tube_has_its_rings_at_the_radius_with_radial_normals(cpu):
    # A natural spline through points on the z axis is the axis itself: C(t) = (0, 0, t).
    axis = np.column_stack([np.zeros(5), np.zeros(5), np.arange(5.0)])
    r = cpu.tubes([axis], "natural", radius=0.3, sides=8, per_segment=2)
    assert r.points.shape == (9 * 8, 3) and r.normals.shape == (9 * 8, 3)
    assert r.triangles.shape == (2 * 8 * 8, 3)
    np.testing.assert_allclose(np.hypot(r.points[:, 0], r.points[:, 1]), 0.3, atol=1e-12)
    np.testing.assert_allclose(r.points[:, 2], r.t, atol=1e-12)
    radial = r.points[:, :2] / 0.3
    np.testing.assert_allclose(r.normals[:, :2], radial, atol=1e-12)
    np.testing.assert_allclose(r.normals[:, 2], 0.0, atol=1e-12)
    np.testing.assert_array_equal(r.curve_offsets, [0, 72])


def test_a_straight_stroke_and_a_ribbon_span_their_width_across_the_curve(cpu):
    line = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]])
    s = cpu.strokes([line], "bezier", width=0.5, per_segment=1)
    assert s.normals is None and s.points.shape == (4, 2)
    got = sorted(map(tuple, np.round(s.points, 12)))
    assert got == [(0.0, -0.25), (0.0, 0.25), (3.0, -0.25), (3.0, 0.25)]
    # A ribbon's two vertices at a point lie its width apart; a natural spline's width
    # coordinate passes through the widths given at the points (t = 0, 1, 2, 3).
    path = np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [2.0, 0.0, 1.0], [3.0, 1.0, 1.0]])
    widths = np.array([0.1, 0.4, 0.2, 0.3])
    r = cpu.ribbons([path], "natural", width=widths, per_segment=1)
    left, right = r.points[0::2], r.points[1::2]
    np.testing.assert_allclose(np.linalg.norm(right - left, axis=1), widths, rtol=1e-12)
    np.testing.assert_allclose((left + right) / 2, path, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(r.normals, axis=1), 1.0, rtol=1e-12)


def test_ragged_lists_stacked_arrays_and_out(cpu):
    stacked = cpu.tubes(LOOPS, radius=0.1, per_segment=4)
    ragged = cpu.tubes(list(LOOPS), radius=0.1, per_segment=4)
    for name, a in stacked.arrays().items():
        np.testing.assert_array_equal(getattr(ragged, name), a, err_msg=name)
    # Curves of different lengths, and the per-curve meshes.
    mixed = cpu.strokes([PATHS[0], PATHS[1][:4]], width=[np.full(6, 0.1), np.full(4, 0.2)],
                        per_segment=3)
    assert len(mixed.curve_offsets) == 3
    one = mixed.curve(1)
    assert one["triangles"].min() == 0
    assert one["triangles"].max() == len(one["points"]) - 1
    # out= fills the same arrays again.
    again = cpu.tubes(LOOPS * 2, radius=0.1, per_segment=4, out=stacked)
    assert again.points is stacked.points and again.normals is stacked.normals
    np.testing.assert_allclose(np.linalg.norm(again.normals, axis=1), 1.0, rtol=1e-12)
    with pytest.raises(ValueError, match='out: "points" has shape'):
        cpu.tubes(LOOPS, radius=0.1, per_segment=5, out=stacked)


def test_meshes_open_in_trimesh(cpu):
    trimesh = pytest.importorskip("trimesh")
    closed = cpu.tubes(LOOPS[:1], "catmull-rom", ends="closed", radius=0.05, per_segment=8)
    mesh = closed.trimesh()
    assert isinstance(mesh, trimesh.Trimesh) and mesh.is_watertight
    flat = cpu.strokes(PATHS, width=0.05).trimesh(2)
    assert np.all(flat.vertices[:, 2] == 0.0)


@pytest.mark.parametrize("call, kwargs, error, match", [
    ("tubes", {"radius": 0.0}, ValueError, 'curve 0: "radius" must be a finite number > 0'),
    ("tubes", {"radius": [np.ones(6)] * 5}, ValueError, 'curve 0: "radius" 6 values for 7'),
    ("tubes", {"radius": 0.1, "sides": 2}, ValueError, 'curve 0: "sides"'),
    ("tubes", {"radius": 0.1, "sides": 2.5}, ValueError, "sides: must be an integer"),
    ("tubes", {"radius": 0.1, "up": [0, 1]}, ValueError, r"up: must be 3 numbers"),
    ("tubes", {"radius": 0.1, "caps": "yes"}, TypeError, "caps: must be True or False"),
    ("tubes", {"radius": 0.1, "dash": [1, 2, 3]}, ValueError,
     'curve 0: "dash" must hold an even number'),
    ("tubes", {"radius": 0.1, "dash_offset": 1.0}, ValueError, "dash_offset: needs a dash"),
    ("tubes", {"radius": 0.1, "at": [0.5]}, ValueError, 'curve 0: "sampling"'),
    ("tubes", {"radius": 0.1, "tolerance": 1e-3, "sides": 3}, ValueError,
     'curve 0: "sides" 3 sides stray'),
    ("tubes", {"radius": 0.1, "tolerance": -1.0}, ValueError, '"tolerance"'),
    ("tubes", {"radius": 0.1, "colour": "red"}, TypeError, "colour"),
    ("strokes", {"width": 0.1}, ValueError, 'curve 0: "geometry" a stroke needs 2-D points'),
])
def test_bad_input_is_named(cpu, call, kwargs, error, match):
    with pytest.raises(error, match=match):
        getattr(cpu, call)(LOOPS, **kwargs)


def test_stroke_fields_are_named(cpu):
    with pytest.raises(ValueError, match='cap: must be "butt", "round" or "square"'):
        cpu.strokes(PATHS, width=0.1, cap="flat")
    with pytest.raises(ValueError, match='curve 0: "miter_limit" must be a finite number >= 1'):
        cpu.strokes(PATHS, width=0.1, miter_limit=0.5)


@pytest.mark.parametrize("method, keywords", [
    ("tubes", {"radius": 0.05, "ends": "closed", "caps": True}),
    ("ribbons", {"width": 0.1, "kind": "natural", "arc_length": 50}),
    ("tubes", {"radius": 0.05, "dash": [0.4, 0.1]}),
    ("tubes", {"radius": 0.05, "ends": "closed", "tolerance": 1e-3}),
])
def test_a_gpu_context_makes_float32_meshes_beside_the_cpus(cpu, gpu, method, keywords):
    want = getattr(cpu, method)(LOOPS, **keywords)
    got = getattr(gpu, method)(LOOPS, **keywords)
    for name in ("t", "triangles", "curve_offsets", "triangle_offsets"):
        np.testing.assert_array_equal(getattr(got, name), getattr(want, name), err_msg=name)
    for name in ("points", "normals"):
        assert getattr(got, name).dtype == np.float32
    np.testing.assert_allclose(got.points, want.points, atol=1e-5)
    # The contract's bound on normals: 1e-3 rad (f32 frames carried over many cross-sections).
    cosines = np.einsum("ij,ij->i", got.normals.astype(np.float64), want.normals)
    angles = np.arccos(np.clip(cosines / np.linalg.norm(got.normals, axis=1), -1.0, 1.0))
    assert angles.max() <= 1e-3, angles.max()
    flat, exact = gpu.strokes(PATHS, width=0.05), cpu.strokes(PATHS, width=0.05)
    assert flat.points.dtype == np.float32 and flat.points.shape[1] == 2
    for name in ("t", "triangles", "curve_offsets", "triangle_offsets"):
        np.testing.assert_array_equal(getattr(flat, name), getattr(exact, name), err_msg=name)
    np.testing.assert_allclose(flat.points, exact.points, atol=1e-5)


def test_curves_that_cannot_be_made_are_named_by_their_index(cpu):
    bad = [LOOPS[0], np.full((5, 3), np.nan)]
    with pytest.raises(ValueError, match='curve 1: "points" must be finite'):
        cpu.tubes(bad, radius=0.1)
    with pytest.raises(ValueError, match='curve 1: "points" needs at least 4 points'):
        cpu.tubes([LOOPS[0], LOOPS[0][:1]], radius=0.1)


def test_a_mesh_that_overflows_is_refused_by_name(cpu):
    # A natural spline along x = 1e308 (its fit exact: the differences are 0): rings of
    # radius 1e308 reach past the largest float64 along x.
    far = np.array([[1e308, 0.0, 0.0], [1e308, 1.0, 0.0], [1e308, 2.0, 0.0], [1e308, 3.0, 0.0]])
    with pytest.raises(ValueError, match="curve 1: mesh vertex 0 is not finite"):
        cpu.tubes([LOOPS[0][:4], far], "natural", radius=1e308, per_segment=2)


_TUBES_UNDER_A_LIMIT = """
import resource, sys, numpy as np, splinegpu
ctx = splinegpu.Context(backend="cpu")
points = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 1], [0, 2, 2]], float)[None]
size = int(open("/proc/self/status").read().split("VmSize:")[1].split()[0]) * 1024
resource.setrlimit(resource.RLIMIT_AS, (size + 700_000_000, resource.RLIM_INFINITY))
for sides in (40, 200):
    try:
        mesh = ctx.tubes(points, radius=0.1, sides=sides, per_segment=20000)
        print("made", mesh.points.shape[0])
    except MemoryError as e:
        print("MemoryError", e)
"""


def test_meshes_past_the_process_limit_are_a_memory_error_not_a_panic(tmp_path):
    """Tubes of 1.6 M and 8 M vertices under an address-space limit (RLIMIT_AS, in a child
    process of its own) about 700 MB above what the interpreter holds: made, or a MemoryError
    (NumPy's refusal became a PanicException, "PyObject pointer is null", before)."""
    import subprocess
    import sys

    done = subprocess.run([sys.executable, "-c", _TUBES_UNDER_A_LIMIT], capture_output=True,
                          text=True, timeout=120, cwd=tmp_path)
    assert done.returncode == 0, done.stderr[-2000:]
    lines = done.stdout.splitlines()
    assert lines[0] == "made 1600040", done.stdout
    assert lines[1].startswith("MemoryError"), (done.stdout, done.stderr[-2000:])
