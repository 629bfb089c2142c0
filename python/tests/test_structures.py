"""Every structure of the engine's registry (dynray.ACCELS), through Python, gives brute
force's answers bit for bit on a decimated bunny, for random and adversarial rays; the
input forms (origins + directions, (N, 8), dtypes, orders, one origin) agree too."""

import numpy as np
import pytest

import dynray
from conftest import primary_rays, random_rays


def bits(a):
    return np.ascontiguousarray(a).view(np.uint8)


def adversarial_rays(mesh):
    """Rays at vertices and edge midpoints (shared edges must not leak), along the axes,
    grazing, with clipped, empty and point intervals, tiny and huge directions."""
    v = mesh.vertices.astype(np.float64)
    f = mesh.faces.astype(np.int64)
    lo, hi = (np.array(b) for b in mesh.bounds)
    c, ext = (lo + hi) / 2, (hi - lo).max()
    rng = np.random.default_rng(3)
    targets = np.concatenate([v[::7], (v[f[::5, 0]] + v[f[::5, 1]]) / 2, v[f[::11]].mean(1)])
    eye = c + rng.normal(size=(len(targets), 3)) * 2 * ext
    rows = [np.c_[eye, targets - eye, np.zeros(len(targets)), np.full(len(targets), np.inf)]]
    for axis in range(3):  # axis-parallel rays through the box, both ways
        o = rng.uniform(lo, hi, (300, 3))
        o[:, axis] = lo[axis] - ext
        d = np.zeros((300, 3))
        d[:, axis] = 1
        rows.append(np.c_[o, d, np.zeros(300), np.full(300, np.inf)])
        rows.append(np.c_[o + 3 * ext * d, -d, np.zeros(300), np.full(300, np.inf)])
    base = random_rays(mesh, 400, 11).astype(np.float64)
    t_near = np.linalg.norm(base[:, 3:6], axis=1)
    for tmin, tmax in [(0.5, 0.5), (2.0, 1.0), (0.0, 0.0), (1e-3, 1e-2)]:
        r = base.copy()
        r[:, 6], r[:, 7] = tmin / t_near * ext, tmax / t_near * ext
        rows.append(r)
    tiny, huge = base.copy(), base.copy()
    tiny[:, 3:6] *= 1e-20
    huge[:, 3:6] *= 1e20
    rows += [tiny, huge]
    starts = np.c_[targets[:200], rng.normal(size=(200, 3)), np.zeros(200), np.full(200, np.inf)]
    rows.append(starts)  # rays starting on the surface
    return np.concatenate(rows).astype(np.float32)


@pytest.fixture(scope="module")
def rays(small_mesh):
    return np.concatenate(
        [random_rays(small_mesh, 3000, 1), primary_rays(small_mesh, 40), adversarial_rays(small_mesh)]
    )


@pytest.fixture(scope="module")
def oracle(small_mesh, rays):
    brute = dynray.build(small_mesh, "brute")
    return brute.intersect(rays), brute.occluded(rays)


def test_registry_lists_every_structure():
    assert dynray.ACCELS[0] == "brute" and "bvh" in dynray.ACCELS and len(dynray.ACCELS) == len(set(dynray.ACCELS))
    assert {"bvh2", "bih", "kdtree", "kdtree-ropes", "octree", "octree-descent", "grid", "apit", "abuffer"} <= set(dynray.ACCELS)


@pytest.mark.parametrize("accel", dynray.ACCELS)
def test_structure_equals_brute_force(small_mesh, rays, oracle, accel):
    hits, occ = oracle
    s = dynray.build(small_mesh, accel)
    assert s.name == accel and s.accel == accel
    got = s.intersect(rays)
    for f in ("t", "prim", "u", "v"):
        diff = np.flatnonzero((bits(got[f]) != bits(hits[f])).reshape(len(rays), -1).any(1))
        assert diff.size == 0, f"{accel}: {f} differs on {diff.size} rays, first {diff[:5]}"
    assert np.array_equal(s.occluded(rays), occ), accel
    stats = s.validate()
    assert stats["memory_bytes"] == s.memory_bytes > 0 and stats["nodes"] >= 1


def test_oracle_sees_hits_misses_and_empty_intervals(oracle, rays):
    hits, occ = oracle
    assert 0.2 < (hits["prim"] >= 0).mean() < 0.9
    miss = hits["prim"] < 0
    assert np.all(np.isinf(hits["t"][miss])) and np.all(hits["u"][miss] == 0)
    assert np.array_equal(occ, ~miss)
    empty = rays[:, 6] > rays[:, 7]
    assert empty.sum() >= 400 and np.all(miss[empty])


@pytest.mark.parametrize(
    "accel,params",
    [("bih", dict(max_prims=5, shrink=False)), ("kdtree:fast", {}), ("octree", dict(preset="high_quality")),
     ("grid", dict(density=3, exact_overlap=False)), ("bvh", dict(leaf_size=2, bins=8))],
)
def test_parameters_keep_the_answers(small_mesh, rays, oracle, accel, params):
    try:
        s = dynray.build(small_mesh, accel, **params)
    except ValueError as e:  # a key this test guessed wrong must say so, not pass
        pytest.fail(f"{accel} {params}: {e}")
    got = s.intersect(rays)
    assert np.array_equal(bits(got["t"]), bits(oracle[0]["t"])) and np.array_equal(got["prim"], oracle[0]["prim"])


def test_input_forms_agree(small_mesh, rays):
    s = dynray.build(small_mesh, "bvh")
    want = s.intersect(rays)
    o, d = rays[:, :3], rays[:, 3:6]
    forms = [
        s.intersect(o, d, rays[:, 6], rays[:, 7]),
        s.intersect(o.astype(np.float64), np.asfortranarray(d), rays[:, 6].astype(np.float64), rays[:, 7]),
        s.intersect(np.asfortranarray(rays)),
        s.intersect(rays.astype(np.float64)),
        s.intersect(rays.tolist()),
        s.intersect(np.repeat(rays, 2, axis=0)[::2]),  # a strided view
    ]
    for i, got in enumerate(forms):
        for f in ("t", "prim", "u", "v"):
            assert np.array_equal(bits(got[f]), bits(want[f])), (i, f)
    one = s.intersect(rays[0, :3], d[:5])  # one origin for every ray
    assert np.array_equal(one["t"], s.intersect(np.repeat(rays[:1, :3], 5, 0), d[:5])["t"])
    default = s.intersect(o, d)  # tmin 0, tmax inf
    full = rays.copy()
    full[:, 6], full[:, 7] = 0, np.inf
    assert np.array_equal(bits(default["t"]), bits(s.intersect(full)["t"]))
    assert s.intersect(rays[:0])["t"].shape == (0,)


def test_normal_and_point_fields(small_mesh, rays):
    s = dynray.build(small_mesh)
    h = s.intersect(rays, normal=True, point=True)
    hit = h["prim"] >= 0
    assert h["normal"].shape == (len(rays), 3) and np.all(np.isnan(h["point"][~hit]))
    v, f = small_mesh.vertices.astype(np.float64), small_mesh.faces[h["prim"][hit]]
    p0, p1, p2 = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    u, w = h["u"][hit, None], h["v"][hit, None]
    assert np.allclose(h["point"][hit], p0 * (1 - u - w) + p1 * u + p2 * w, atol=1e-5)
    n = np.cross(p1 - p0, p2 - p0)
    assert np.allclose(h["normal"][hit], n / np.linalg.norm(n, axis=1, keepdims=True), atol=1e-5)
    at = rays[hit, :3] + h["t"][hit, None] * rays[hit, 3:6]
    near = np.abs(rays[hit, 3:6]).max(1) < 1e3
    assert np.allclose(at[near], h["point"][hit][near], atol=1e-4)


def test_refit_follows_moved_vertices(small_mesh, rays):
    moved = small_mesh.vertices * np.float32(1.5) + np.float32(0.01)
    want = dynray.build(dynray.Mesh(moved, small_mesh.faces), "brute").intersect(rays)
    for accel in ("bvh", "bih"):
        s = dynray.build(small_mesh, accel)
        assert s.refits
        s.refit(moved)
        got = s.intersect(rays)
        assert np.array_equal(bits(got["t"]), bits(want["t"])) and np.array_equal(got["prim"], want["prim"]), accel
        assert np.array_equal(s.mesh.vertices, moved) and not np.array_equal(small_mesh.vertices, moved)
        s.validate()


def test_threads_argument_gives_the_same_answers(small_mesh, rays):
    s = dynray.build(small_mesh, "kdtree", threads=1)
    a = s.intersect(rays, threads=1)
    b = s.intersect(rays, threads=3)
    assert np.array_equal(bits(a["t"]), bits(b["t"])) and np.array_equal(s.occluded(rays, threads=2), s.occluded(rays))


def test_accel_params_lists_keys_and_presets():
    p = dynray.accel_params("bih")
    assert "max_prims" in p["keys"] and "preset" in p["keys"] and "default" in p["presets"]
