"""Bad inputs raise the documented exceptions (ValueError, TypeError, OSError naming the
file), with the engine's messages, and never crash the interpreter."""

import numpy as np
import pytest

import dynray
from conftest import BUNNY

V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
F = np.array([[0, 1, 2]], np.int32)


@pytest.mark.parametrize(
    "vertices,faces,exc,match",
    [
        (V[:, :2], F, ValueError, r"vertices must have shape \(N, 3\), found \[3, 2\]"),
        (V, F[:, :2], ValueError, r"faces must have shape \(N, 3\)"),
        (V.ravel(), F, ValueError, "vertices must have shape"),
        (np.where(V == 1, np.nan, V), F, ValueError, "vertices row 1 has a non-finite value"),
        (np.where(V == 1, np.inf, V), F, ValueError, "non-finite"),
        (V, F + 1, ValueError, r"faces row 0: index 3 is outside 0..3"),
        (V, -F - 1, ValueError, "index -1 is outside"),
        (V, np.array([[0, 1, 2**40]]), ValueError, "index 1099511627776 is outside"),
        (V, F[:0], ValueError, "no triangles"),
        (V.astype(bool), F, TypeError, r"vertices must be a real numeric array \(floats or integers\), found bool"),
        (V.astype(np.complex64), F, TypeError, "found complex64"),
        (V, F.astype(np.int16), TypeError, "faces must be int32, int64, uint32 or uint64, found int16"),
        (V, F.astype(np.float32), TypeError, "found float32"),
        ("abc", F, ValueError, "vertices must have shape"),
    ],
)
def test_bad_meshes(vertices, faces, exc, match):
    with pytest.raises(exc, match=match):
        dynray.Mesh(vertices, faces)


def test_accepted_mesh_dtypes_and_orders():
    for fd in (np.int32, np.int64, np.uint32, np.uint64):
        for vd in (np.float32, np.float64):
            m = dynray.Mesh(np.asfortranarray(V.astype(vd)), np.asfortranarray(F.astype(fd)))
            assert m.triangle_count == 1 and np.array_equal(m.vertices, V) and m.faces.dtype == np.uint32


def test_any_real_numeric_array_is_read(bunny):
    """Issue 48: integer and list coordinates, and float16, are read as the numbers they
    hold (integer directions were refused while integer origins were accepted)."""
    for vd in (np.int32, np.int64, np.uint8, np.float16):
        m = dynray.Mesh(V.astype(vd), F)
        assert np.array_equal(m.vertices, V)
    bvh = dynray.build(bunny.mesh, "bvh")
    # The bunny stands about 0.03..0.19 high: a ray at y = 0.125 (exact in every dtype
    # as 1/8 of an integer grid) hits it.
    want = bvh.intersect(np.float32([[0, 0.125, 1]]), np.float32([[0, 0, -1]]))
    for origins, directions in [
        ([[0, 0.125, 1]], [[0, 0, -1]]),
        (np.float16([[0, 0.125, 1]]), np.int32([[0, 0, -1]])),
        ([0, 0.125, 1], np.int8([[0, 0, -1]])),
    ]:
        got = bvh.intersect(origins, directions, tmin=0, tmax=np.int64([10]))
        assert got["prim"][0] == want["prim"][0] != -1 and got["t"][0] == want["t"][0]
    with pytest.raises(TypeError, match="directions must be a real numeric array"):
        bvh.intersect([[0, 0, 1]], [[True, False, True]])


def test_load_errors_name_the_file(tmp_path):
    missing = tmp_path / "nope.ply"
    with pytest.raises(FileNotFoundError) as e:
        dynray.load(missing)
    assert e.value.filename == str(missing) and "nope.ply" in str(e.value)
    with pytest.raises(ValueError, match=r"mesh\.xyz: unknown file type"):
        dynray.load(tmp_path / "mesh.xyz")
    bad = tmp_path / "bad.ply"
    bad.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n")
    with pytest.raises(ValueError, match="bad.ply"):
        dynray.load(bad)
    obj = tmp_path / "bad.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nf 1 2 9\n")
    with pytest.raises(ValueError, match="bad.obj"):
        dynray.load(obj)


def test_build_errors_are_the_engines():
    m = dynray.Mesh(V, F)
    with pytest.raises(ValueError, match="unknown structure `nope`"):
        dynray.build(m, "nope")
    with pytest.raises(ValueError, match="max_prims"):
        dynray.build(m, "bih", max_prims=0)
    with pytest.raises(ValueError, match="colour"):
        dynray.build(m, "bih", colour=3)
    with pytest.raises(ValueError, match="preset"):
        dynray.build(m, "kdtree:slowest")
    with pytest.raises(TypeError):
        dynray.build([V, F])
    with pytest.raises(ValueError, match="threads must be at least 1"):
        dynray.build(m, threads=0)


def test_query_errors():
    s = dynray.build(dynray.Mesh(V, F))
    rays = np.zeros((4, 8), np.float32)
    rays[:, 0], rays[:, 1], rays[:, 2] = [0.2, 2, 3, 4], 0.2, 1  # the first one above the triangle
    rays[:, 5], rays[:, 7] = -1, np.inf
    with pytest.raises(ValueError, match=r"rays must have shape \(N, 8\), found \[4, 7\]"):
        s.intersect(rays[:, :7])
    bad = rays.copy()
    bad[2, 0] = np.nan
    with pytest.raises(ValueError, match="ray 2 has a non-finite origin"):
        s.intersect(bad)
    bad = rays.copy()
    bad[3, 6] = np.nan
    with pytest.raises(ValueError, match="ray 3 has a NaN tmin or tmax"):
        s.occluded(bad)
    with pytest.raises(ValueError, match="3 origins but 4 directions"):
        s.intersect(rays[:3, :3], rays[:, 3:6])
    with pytest.raises(ValueError, match="tmin and tmax come from columns 6 and 7"):
        s.intersect(rays, tmin=0.5)
    with pytest.raises(ValueError, match=r"tmax must be a number or have shape \(4,\)"):
        s.intersect(rays[:, :3], rays[:, 3:6], tmax=np.ones(3))
    with pytest.raises(TypeError, match="rays must be a real numeric array .*, found complex128"):
        s.intersect(np.zeros((4, 8), np.complex128))
    # Integer rays are read as the numbers they hold (issue 48).
    finite = rays.copy()
    finite[:, 7] = 10
    whole = np.trunc(finite)
    assert s.intersect(whole.astype(np.int64))["t"].tolist() == s.intersect(whole)["t"].tolist()
    assert s.intersect(rays)["prim"].tolist() == [0, -1, -1, -1]  # still usable


def test_refit_errors():
    m = dynray.Mesh(V, F)
    with pytest.raises(NotImplementedError, match="kdtree does not refit"):
        dynray.build(m, "kdtree").refit(V)
    s = dynray.build(m, "bvh")
    with pytest.raises(ValueError, match="refit: 2 vertices given, the mesh has 3"):
        s.refit(V[:2])
    with pytest.raises(ValueError, match="non-finite"):
        s.refit(np.full((3, 3), np.nan, np.float32))


def test_trace_rays_errors_are_the_clis(tmp_path):
    rays = np.zeros((2, 8), np.float32)
    np.save(tmp_path / "rays.npy", rays)
    with pytest.raises(ValueError, match=r"hits\.npy: trace-rays writes a \.npz archive"):
        dynray.trace_rays(BUNNY, tmp_path / "rays.npy", tmp_path / "hits.npy")
    with pytest.raises(OSError, match=r"missing\.npy: cannot open"):
        dynray.trace_rays(BUNNY, tmp_path / "missing.npy", tmp_path / "hits.npz")
    np.save(tmp_path / "r7.npy", rays[:, :7])
    with pytest.raises(ValueError, match=r"rays must have shape \(N, 8\), found \[2, 7\]"):
        dynray.trace_rays(BUNNY, tmp_path / "r7.npy", tmp_path / "hits.npz")
    with pytest.raises(FileNotFoundError, match="nothing.ply"):
        dynray.trace_rays(tmp_path / "nothing.ply", tmp_path / "rays.npy", tmp_path / "hits.npz")
    with pytest.raises(ValueError, match="unknown hit field `depth`"):
        dynray.trace_rays(BUNNY, tmp_path / "rays.npy", tmp_path / "hits.npz", fields=["t", "depth"])
    with pytest.raises(ValueError, match="fields cannot be given with occluded=True"):
        dynray.trace_rays(BUNNY, tmp_path / "rays.npy", tmp_path / "hits.npz", occluded=True, fields=["t"])
    assert not (tmp_path / "hits.npz").exists()


def test_render_errors(bunny):
    with pytest.raises(ValueError, match="unknown integrator `path-tracer`"):
        dynray.render(bunny, 8, 8, 1, "path-tracer")
    with pytest.raises(ValueError, match="image width 0 is outside"):
        dynray.render(bunny, 0, 8, 1)
    with pytest.raises(ValueError, match="spp must be in 1..=65536"):
        dynray.render(bunny, 8, 8, 0)
    with pytest.raises(TypeError, match="scene must be a dynray.Scene or a file path"):
        dynray.render(42, 8, 8)
