"""Context.tessellate_surfaces: the command line's NPZ bit for bit (every surface kind, every
sampling, derivatives and normals, the Utah teapot's patch list), out= reuse, the GPU within
the contract's surface promise, a trimesh-ready mesh, and bad input named."""

from __future__ import annotations

import json
import pathlib

import numpy as np
import pytest
from test_tessellate import cli_npz

import splinegpu

ROOT = pathlib.Path(__file__).resolve().parents[2]
CPU = splinegpu.Context("cpu")


def torus(n_u: int = 8, n_v: int = 6, big: float = 3.0, small: float = 1.0) -> np.ndarray:
    a = np.linspace(0, 2 * np.pi, n_u, endpoint=False)[:, None]
    b = np.linspace(0, 2 * np.pi, n_v, endpoint=False)[None, :]
    return np.stack([(big + small * np.cos(b)) * np.cos(a), (big + small * np.cos(b)) * np.sin(a),
                     small * np.sin(b) + 0 * a], axis=-1)


def wavy(n_u: int, n_v: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    u, v = np.meshgrid(np.arange(n_u, dtype=float), np.arange(n_v, dtype=float), indexing="ij")
    return np.stack([u, v, rng.normal(size=u.shape)], axis=-1)


def document(nets, kind, fields, sampling, derivatives=0, normals=False):
    surfaces = []
    for s, net in enumerate(nets):
        entry = {"kind": kind, "points": net.tolist()}
        for name, value in fields.items():
            # Array fields may be given per surface (a list); "ends" and "conditions" are pairs.
            per_surface = name in ("u", "v", "knots_u", "knots_v", "weights")
            value = value[s] if per_surface and isinstance(value, list) else value
            entry[name] = value.tolist() if isinstance(value, np.ndarray) else value
        surfaces.append(entry)
    return {"sampling": sampling, "derivatives": derivatives, "normals": normals,
            "surfaces": surfaces}


NETS = [wavy(6, 5, 1), wavy(7, 9, 2)]
KNOTS = [np.r_[0, 0, 0, 0, 1, 2, 3, 3, 3, 3.0], np.r_[0, 0, 0, 0, 0.5, 3, 3, 3, 3.0]]
CASES = [
    ("bspline", {"ends": ["repeat", "control"]}, ("per_segment", [3, 2])),
    ("catmull-rom", {}, ("per_segment", 4)),
    ("cardinal", {"tension": 0.3, "ends": "repeat"}, ("tolerance", 0.05)),
    ("beta", {"bias": 1.5, "tension": 2.0}, ("at", [[0.5, 0.5], [1.0, 1.25]])),
    ("interpolating", {"conditions": ["natural", "not-a-knot"]}, ("per_segment", 3)),
]


def python_fields(fields: dict) -> dict:
    out = {}
    for name, value in fields.items():
        out[name] = tuple(value) if name in ("ends", "conditions") and isinstance(value, list) \
            else value
    return out


def sampling_kw(sampling) -> dict:
    name, value = sampling
    if name == "at":
        value = np.asarray(value, dtype=float)
    return {name: value}


def assert_same(result: splinegpu.SurfaceTessellation, npz: dict):
    arrays = result.arrays()
    assert sorted(arrays) == sorted(npz)
    for name, want in npz.items():
        assert arrays[name].dtype == want.dtype, name
        np.testing.assert_array_equal(arrays[name], want, err_msg=name)


@pytest.mark.parametrize("kind, fields, sampling", CASES)
@pytest.mark.parametrize("derivatives", [0, 2])
def test_nets_equal_the_command_line(kind, fields, sampling, derivatives):
    result = CPU.tessellate_surfaces(NETS, kind, **python_fields(fields),
                                     **sampling_kw(sampling), derivatives=derivatives,
                                     normals=True)
    want = cli_npz(document(NETS, kind, fields, {sampling[0]: sampling[1]}, derivatives,
                            normals=True))
    assert_same(result, want)


def test_nurbs_with_weights_and_a_closed_torus_equal_the_command_line():
    nets = [wavy(6, 5, 3), wavy(6, 5, 4)]
    weights = [np.full((6, 5), 1.0), np.random.default_rng(5).uniform(0.5, 2, (6, 5))]
    result = CPU.tessellate_surfaces(nets, "nurbs", knots_u=KNOTS[0], knots_v=KNOTS[1],
                                     weights=weights, per_segment=(2, 3), derivatives=1)
    want = cli_npz(document(nets, "nurbs", {"knots_u": KNOTS[0], "knots_v": KNOTS[1],
                                            "weights": weights}, {"per_segment": [2, 3]}, 1))
    assert_same(result, want)
    tori = [torus()]
    result = CPU.tessellate_surfaces(tori, "bspline", ends="closed", tolerance=0.01,
                                     normals=True)
    want = cli_npz(document(tori, "bspline", {"ends": "closed"}, {"tolerance": 0.01},
                            normals=True))
    assert_same(result, want)
    # Closed both ways and watertight: every edge in exactly two triangles.
    edges = np.sort(result.triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert (counts == 2).all()


def test_the_teapot_equals_the_command_line_and_opens_in_trimesh():
    doc = json.loads((ROOT / "crates/splinegpu-cli/examples/teapot.json").read_text())
    surface = doc["surfaces"][0]
    points = np.asarray(surface["points"], dtype=float)
    patches = np.asarray(surface["patches"])
    result = CPU.tessellate_surfaces([points], "bezier", patches=patches,
                                     tolerance=doc["sampling"]["tolerance"], normals=True)
    assert_same(result, cli_npz(doc))
    assert result.patch is not None and (result.patch >= 0).all()
    trimesh = pytest.importorskip("trimesh")
    mesh = result.trimesh()
    assert isinstance(mesh, trimesh.Trimesh)
    assert len(mesh.faces) == len(result.triangles)
    assert np.shares_memory(mesh.vertices, result.points)  # float64: no copy


def test_out_refills_the_same_arrays():
    first = CPU.tessellate_surfaces(NETS, "bspline", per_segment=3, derivatives=2, normals=True)
    kept = dict(first.arrays().items())
    moved = [net + 1.0 for net in NETS]
    again = CPU.tessellate_surfaces(moved, "bspline", per_segment=3, derivatives=2,
                                    normals=True, out=first)
    fresh = CPU.tessellate_surfaces(moved, "bspline", per_segment=3, derivatives=2,
                                    normals=True)
    for name in ("points", "du", "normals", "uv", "triangles"):
        assert getattr(again, name) is kept[name], name
        np.testing.assert_array_equal(getattr(again, name), getattr(fresh, name))
    frozen = CPU.tessellate_surfaces(NETS, "bspline", per_segment=3)
    frozen.points.flags.writeable = False
    with pytest.raises(ValueError, match='out: "points" must be writeable'):
        CPU.tessellate_surfaces(NETS, "bspline", per_segment=3, out=frozen)
    fortran = CPU.tessellate_surfaces(NETS, "bspline", per_segment=3)
    fortran.points = np.asfortranarray(fortran.points)
    with pytest.raises(ValueError, match='out: "points" must be C-contiguous'):
        CPU.tessellate_surfaces(NETS, "bspline", per_segment=3, out=fortran)
    with pytest.raises(ValueError, match='out: "uv" has shape'):
        CPU.tessellate_surfaces(NETS, "bspline", per_segment=4, out=first)


def test_gpu_surfaces_within_the_contracts_promise():
    try:
        gpu = splinegpu.Context("gpu")
    except RuntimeError:
        pytest.skip("no adapter")
    nets = [wavy(6, 5, 6) + 1e5, torus() * 10]
    for kwargs in ({"per_segment": 4}, {"tolerance": 0.05}):
        want = CPU.tessellate_surfaces(nets, "bspline", derivatives=1, normals=True, **kwargs)
        got = gpu.tessellate_surfaces(nets, "bspline", derivatives=1, normals=True, **kwargs)
        assert got.points.dtype == np.float32
        np.testing.assert_array_equal(got.uv, want.uv)
        np.testing.assert_array_equal(got.triangles, want.triangles)
        # Position: 1e-5 of the extent plus a few ulp of the coordinates (contract).
        scale = 1e-5 * 10 * 4 + 8 * np.spacing(np.float32(2e5))
        assert np.abs(got.points - want.points).max() <= scale
        cos = np.sum(got.normals * want.normals, axis=1)
        assert np.arccos(np.clip(cos, -1, 1)).max() <= 1e-3


def test_bad_input_is_named():
    with pytest.raises(ValueError, match=r"surface 1: .*points"):
        CPU.tessellate_surfaces([NETS[0], NETS[1][..., :2] * np.nan], "bspline")
    with pytest.raises(ValueError, match="is not a surface kind"):
        CPU.tessellate_surfaces(NETS, "akima")
    with pytest.raises(ValueError, match="conditions"):
        CPU.tessellate_surfaces(NETS, "interpolating")
    with pytest.raises(ValueError, match="normals"):
        CPU.tessellate_surfaces([NETS[0][..., :2]], "bspline", normals=True)
    with pytest.raises(MemoryError, match="the sampling gives meshes"):
        CPU.tessellate_surfaces(NETS, "bspline", per_segment=2**32 - 1)
    with pytest.raises(ValueError, match="per_segment: must be a count"):
        CPU.tessellate_surfaces(NETS, "bspline", per_segment=2**40)
    with pytest.raises(ValueError, match="sampling: give one of"):
        CPU.tessellate_surfaces(NETS, "bspline", per_segment=2, tolerance=0.1)
    with pytest.raises(ValueError, match=r"nets\[0\]: a net must be"):
        CPU.tessellate_surfaces([np.zeros((4, 3))], "bspline")
    with pytest.raises(ValueError, match=r"patches\[0\]"):
        CPU.tessellate_surfaces([np.zeros((16, 3))], "bezier", patches=np.zeros((1, 15), int))
    with pytest.raises(ValueError, match="surface 0"):
        CPU.tessellate_surfaces([np.zeros((16, 3))], "bezier",
                                patches=np.arange(16).reshape(1, 16) + 1)
    # An unsigned index past int64 is named as given (it wrapped to "= -1" before).
    huge = np.arange(16, dtype=np.uint64).reshape(1, 16)
    huge[0, 3] = 2**64 - 1
    with pytest.raises(ValueError, match=r"patches\[0\]: index 18446744073709551615"):
        CPU.tessellate_surfaces([np.zeros((16, 3))], "bezier", patches=huge)
    # A field the kind does not take is refused, as the command line refuses it.
    with pytest.raises(ValueError, match=r"is not a field of a \"bezier\" surface"):
        CPU.tessellate_surfaces([np.zeros((4, 4, 3))], "bezier", tension=0.5)


@pytest.mark.parametrize("backend", ["cpu", "gpu"])
def test_a_surface_that_overflows_is_refused_by_name(backend, request):
    """A net of cardinal tension 1e308 overflows float64 (and float32 on the GPU): refused with
    the surface and the vertex, as the command line refuses it, never NaN returned."""
    ctx = request.getfixturevalue(backend)
    with pytest.raises(ValueError, match=r"surface 0: vertex \d+ is not finite"):
        ctx.tessellate_surfaces([NETS[0]], "cardinal", tension=1e308, per_segment=2)
