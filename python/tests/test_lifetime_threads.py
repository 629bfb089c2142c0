"""Reference counting (objects freed; a mesh kept alive while a structure uses it) and
the GIL (released while tracing: several Python threads trace at once and get the
answers of a serial run)."""

import gc
import threading
import time
import weakref

import numpy as np

import dynray
from conftest import random_rays


def test_mesh_lives_while_a_structure_uses_it(small_mesh):
    m = dynray.Mesh(small_mesh.vertices, small_mesh.faces)
    ref = weakref.ref(m)
    s = dynray.build(m, "bvh")
    rays = random_rays(m, 500, 5)
    want = s.intersect(rays)
    del m
    gc.collect()
    assert ref() is not None and s.mesh is ref()
    got = s.intersect(rays, normal=True)
    assert np.array_equal(got["t"], want["t"])
    sref = weakref.ref(s)
    del s
    gc.collect()
    assert sref() is None and ref() is None
    assert got["t"].shape == (500,) and got["normal"].sum() != 0  # results own their memory


def test_refit_releases_the_old_mesh(small_mesh):
    m = dynray.Mesh(small_mesh.vertices, small_mesh.faces)
    ref = weakref.ref(m)
    s = dynray.build(m, "bih")
    del m
    s.refit(small_mesh.vertices + np.float32(1))
    gc.collect()
    assert ref() is None and s.mesh.vertex_count == small_mesh.vertex_count


def test_many_structures_are_freed(small_mesh):
    refs = [weakref.ref(dynray.build(small_mesh, a)) for a in dynray.ACCELS for _ in range(3)]
    gc.collect()
    assert all(r() is None for r in refs)
    scene_refs = []
    for _ in range(5):
        sc = dynray.load(small_mesh_file(small_mesh))
        scene_refs.append(weakref.ref(sc.mesh))
        del sc
    gc.collect()
    assert all(r() is None for r in scene_refs)


def small_mesh_file(mesh, _cache={}):
    if "path" not in _cache:
        import tempfile

        d = tempfile.mkdtemp()
        _cache["path"] = f"{d}/small.npz"
        np.savez(_cache["path"], vertices=mesh.vertices, faces=mesh.faces)
    return _cache["path"]


def test_threads_trace_at_once_and_agree_with_serial(bunny):
    s = dynray.build(bunny.mesh, "bvh")
    sets = [random_rays(bunny.mesh, 60000, seed) for seed in range(6)]
    serial = [(s.intersect(r), s.occluded(r)) for r in sets]
    results = [None] * len(sets)

    def work(i):
        results[i] = (s.intersect(sets[i], threads=1), s.occluded(sets[i]))

    threads = [threading.Thread(target=work, args=(i,)) for i in range(len(sets))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for (a, ao), (b, bo) in zip(results, serial):
        assert np.array_equal(a["t"].view(np.uint32), b["t"].view(np.uint32))
        assert np.array_equal(a["prim"], b["prim"]) and np.array_equal(ao, bo)


def test_the_gil_is_released_while_tracing(bunny):
    """A Python thread keeps running during one long query: with the GIL held it could
    not run a single bytecode between the call's start and end."""
    s = dynray.build(bunny.mesh, "brute")  # slow on purpose: the call lasts a while
    rays = random_rays(bunny.mesh, 1000, 9)
    ticks, stop = [], threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    t = threading.Thread(target=tick)
    t.start()
    time.sleep(0.02)
    t0 = time.perf_counter()
    s.intersect(rays, threads=1)
    t1 = time.perf_counter()
    stop.set()
    t.join()
    during = [x for x in ticks if t0 < x < t1]
    assert t1 - t0 > 0.05, "the query was too short to tell"
    assert len(during) >= 5, f"{len(during)} ticks in {t1 - t0:.3f} s of tracing"


def test_refit_while_other_threads_trace(small_mesh):
    """Queries and refits from several threads: every answer is the old or the new
    mesh's, never a mix or a crash."""
    s = dynray.build(small_mesh, "bvh")
    rays = random_rays(small_mesh, 5000, 2)
    a = s.intersect(rays)["t"].view(np.uint32).copy()
    moved = small_mesh.vertices * np.float32(1.01)
    b = dynray.build(dynray.Mesh(moved, small_mesh.faces), "brute").intersect(rays)["t"].view(np.uint32)
    seen, errors = [], []

    def trace():
        try:
            for _ in range(10):
                seen.append(s.intersect(rays)["t"].view(np.uint32).copy())
        except Exception as e:  # pragma: no cover - reported below
            errors.append(e)

    threads = [threading.Thread(target=trace) for _ in range(3)]
    for t in threads:
        t.start()
    for i in range(10):
        s.refit(moved if i % 2 == 0 else small_mesh.vertices)
    for t in threads:
        t.join()
    assert not errors
    assert all(np.array_equal(x, a) or np.array_equal(x, b) for x in seen)
