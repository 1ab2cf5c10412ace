"""Context.closest and Context.intersections: certified answers against hand-derived ones and
a dense brute force, the command line's arrays, and every bad argument refused by name."""

import numpy as np
import pytest

import splinegpu

CPU = splinegpu.Context("cpu")

# Two straight Bezier segments, y = 0 and y = 5 for x in [0, 3] (x = 3t).
LINES = np.array([[[0, 0], [1, 0], [2, 0], [3, 0]], [[0, 5], [1, 5], [2, 5], [3, 5]]], float)


def test_hand_derived_answers():
    result = CPU.closest(LINES, "bezier", [[1.5, 2], [1, 4], [-1, -1]])
    assert result.curve.dtype == np.int64 and result.curve.tolist() == [0, 1, 0]
    np.testing.assert_allclose(result.t, [0.5, 1 / 3, 0.0], atol=1e-12)
    np.testing.assert_allclose(result.point, [[1.5, 0], [1, 5], [0, 0]], atol=1e-12)
    np.testing.assert_allclose(result.distance, [2, 1, np.sqrt(2)], atol=1e-12)
    assert len(result) == 3 and set(result.arrays()) == {"curve", "t", "point", "distance"}


def brute_force(curves, kind, queries):
    """The least distance from each query to the curves' samples, by dense sampling (every
    curve at 20,001 points of its parameter range)."""
    dense = CPU.tessellate(curves, kind, per_segment=2000)
    d = np.linalg.norm(dense.points[None, :, :] - queries[:, None, :], axis=2)
    return d.min(axis=1)


def test_against_dense_sampling_on_random_curves():
    rng = np.random.default_rng(5)
    curves = [rng.uniform(-2, 2, (n, 2)) for n in (5, 8, 11)]
    queries = rng.uniform(-3, 3, (200, 2))
    result = CPU.closest(curves, "catmull-rom", queries)
    sampled = brute_force(curves, "catmull-rom", queries)
    # Never farther than a sample (the samples' spacing bounds how much nearer they can be).
    assert np.all(result.distance <= sampled + 1e-12)
    assert np.all(result.distance >= sampled - 1e-2)
    # The point is at the reported distance.
    np.testing.assert_allclose(np.linalg.norm(result.point - queries, axis=1), result.distance,
                               atol=1e-12)


def test_views_fortran_order_and_one_point():
    queries = np.asfortranarray(np.array([[1.5, 2.0, 9.0], [1.0, 4.0, 9.0]])[:, :2])
    queries.flags.writeable = False
    want = CPU.closest(LINES, "bezier", np.ascontiguousarray(queries))
    got = CPU.closest(LINES, "bezier", queries)
    np.testing.assert_array_equal(got.distance, want.distance)
    one = CPU.closest(list(LINES), "bezier", [1.5, 2.0])
    assert one.curve.tolist() == [0] and one.distance.tolist() == [2.0]


@pytest.mark.parametrize("points, error, match", [
    ([[0, 0, 0]], ValueError, "points: must have 2 columns"),
    ([[0, np.nan]], ValueError, "points: query 0 has a coordinate that is not finite"),
    ([[[0, 0]]], ValueError, "points: must be a \\(Q, D\\) array"),
    ([["a", "b"]], TypeError, "points: must be numbers"),
    ([[1 + 1j, 0]], ValueError, "points: complex values"),
])
def test_bad_query_points_are_refused_by_name(points, error, match):
    with pytest.raises(error, match=match):
        CPU.closest(LINES, "bezier", points)


def test_bad_curves_are_refused_naming_the_curve():
    with pytest.raises(ValueError, match="curve 1"):
        CPU.closest([LINES[0], LINES[1][:2]], "bezier", [[0, 0]])
    with pytest.raises(ValueError, match="curves: must be a \\(C, n, D\\) array"):
        CPU.closest(np.zeros((2, 4)), "bezier", [[0, 0]])
    with pytest.raises(TypeError, match="points="):
        CPU.closest(LINES, "bezier")


# The diagonals of [0, 3]^2 cross at (1.5, 1.5); y = 0.5 crosses them at x = 0.5 and 2.5.
DIAGONALS = np.array([[[0, 0], [1, 1], [2, 2], [3, 3]], [[0, 3], [1, 2], [2, 1], [3, 0]],
                      [[0, 0.5], [1, 0.5], [2, 0.5], [3, 0.5]]], float)


def test_intersections_hand_derived():
    r = CPU.intersections(DIAGONALS, "bezier")
    assert r.i.tolist() == [0, 0, 1] and r.j.tolist() == [1, 2, 2]
    np.testing.assert_allclose(r.t_i, [0.5, 1 / 6, 5 / 6], atol=1e-12)
    np.testing.assert_allclose(r.point, [[1.5, 1.5], [0.5, 0.5], [2.5, 0.5]], atol=1e-12)
    assert r.tangent.dtype == np.bool_ and not r.tangent.any() and not r.overlap.any()
    listed = CPU.intersections(DIAGONALS, "bezier", pairs=np.array([[2, 1], [0, 0]]))
    assert listed.i.tolist() == [2] and listed.j.tolist() == [1]
    np.testing.assert_allclose(listed.t_i, [5 / 6], atol=1e-12)


def test_a_loop_meets_itself_once():
    r = CPU.intersections([[[0, 0], [4, 4], [-1, 4], [3, 0]]], "bezier", pairs=[[0, 0]])
    assert len(r) == 1 and r.t_i[0] < r.t_j[0]


@pytest.mark.parametrize("pairs, match", [
    ("some", "pairs: must be \"all\""),
    ([[0, 1, 2]], "pairs: must be \"all\" or \\(K, 2\\) integer"),
    ([[0.5, 1]], "integer curve indices"),
    ([[0, 3]], "pairs: pair 0 = \\[0, 3\\] names a curve that is not there"),
    ([[-1, 0]], "pairs: pair 0"),
])
def test_bad_pairs_are_refused_by_name(pairs, match):
    with pytest.raises(ValueError, match=match):
        CPU.intersections(DIAGONALS, "bezier", pairs=pairs)


def test_intersections_need_2d_curves():
    with pytest.raises(ValueError, match=r"curve 0.*2 coordinates"):
        CPU.intersections(np.zeros((2, 4, 3)) + np.arange(4)[None, :, None], "bezier")


# A flat bicubic Bezier patch over [0, 3]^2 at z = 0 (x = 3u, y = 3v).
FLAT = np.stack([*np.meshgrid(np.arange(4.0), np.arange(4.0), indexing="ij"), np.zeros((4, 4))],
                axis=-1)


def test_closest_on_surfaces_and_rays_hand_derived():
    r = CPU.closest_on_surfaces(FLAT, "bezier", [[1, 2, 5], [4, 4, 0]])
    np.testing.assert_allclose(r.distance, [5, np.sqrt(2)], atol=1e-12)
    np.testing.assert_allclose(r.point, [[1, 2, 0], [3, 3, 0]], atol=1e-9)
    np.testing.assert_allclose([r.u[0], r.v[0]], [1 / 3, 2 / 3], atol=1e-9)
    assert r.patch.tolist() == [-1, -1] and r.surface.tolist() == [0, 0]
    hits = CPU.rays(FLAT, "bezier", [[1, 2, 5, 0, 0, -1], [1, 2, 5, 0, 0, 1]])
    assert hits.hit.tolist() == [True, False] and hits.surface.tolist() == [0, -1]
    np.testing.assert_allclose(hits.s[0], 5, atol=1e-9)
    assert abs(abs(hits.normal[0, 2]) - 1) < 1e-12 and np.isnan(hits.s[1])
    points = FLAT.reshape(16, 3)
    listed = CPU.rays([points], "bezier", [1, 2, 5, 0, 0, -1], patches=[list(range(16))])
    assert listed.patch.tolist() == [0]


@pytest.mark.parametrize("rays, match", [
    ([[0, 0, 0, 0, 0, 0]], "rays: ray 0 has a zero direction"),
    ([[0, 0, 0, 1, 0]], "rays: must be a \\(Q, 6\\) array"),
    ([[0, 0, np.inf, 1, 0, 0]], "rays: ray 0 has a value that is not finite"),
])
def test_bad_rays_are_refused_by_name(rays, match):
    with pytest.raises(ValueError, match=match):
        CPU.rays(FLAT, "bezier", rays)


def test_surface_queries_refuse_the_wrong_dimension():
    with pytest.raises(ValueError, match="points: must have 3 columns"):
        CPU.closest_on_surfaces(FLAT, "bezier", [[1, 2]])
    with pytest.raises(ValueError, match="rays meet 3-D surfaces"):
        CPU.rays(FLAT[:, :, :2], "bezier", [[0, 0, 0, 1, 0, 0]])


def test_a_gpu_context_answers_in_float32_within_the_gpu_bound(gpu):
    """The GPU's closest points and rays: float32 points, distances and normals, float64
    parameters, each distance within the contract's GPU bound (at least 1e-5 E for the position
    plus 1e-5 (E + |q|)) of the CPU's certified one."""
    rng = np.random.default_rng(8)
    curves = [rng.uniform(-2, 2, (n, 2)) for n in (5, 8, 11)]
    queries = rng.uniform(-3, 3, (300, 2))
    want = CPU.closest(curves, "catmull-rom", queries)
    got = gpu.closest(curves, "catmull-rom", queries)
    assert got.point.dtype == np.float32 and got.distance.dtype == np.float32
    assert got.t.dtype == np.float64 and got.curve.dtype == np.int64
    bound = 2e-5 * 4 + 1e-5 * np.abs(queries).max(axis=1)
    assert np.all(np.abs(got.distance - want.distance) <= bound)
    surface = gpu.closest_on_surfaces(FLAT, "bezier", [[1, 2, 5], [4, 4, 0]])
    assert surface.point.dtype == np.float32 and surface.u.dtype == np.float64
    np.testing.assert_allclose(surface.distance, [5, np.sqrt(2)], atol=2e-4)
    hits = gpu.rays(FLAT, "bezier", [[1, 2, 5, 0, 0, -1], [1, 2, 5, 0, 0, 1]])
    assert hits.hit.tolist() == [True, False] and hits.normal.dtype == np.float32
    assert abs(hits.s[0] - 5) <= 2e-4 and np.isnan(hits.s[1]) and hits.s.dtype == np.float64
