"""dynray.distributed on a Dask LocalCluster of 2 worker processes (docs/python.md,
"Distributed"): 2M rays at the bunny give exactly one process's Structure.intersect and
occluded arrays, from a .npy path and from an in-memory array; with out_path, the
archive `dynray trace-rays` writes, byte for byte; each worker process loads and builds
once and keeps the structure for its later tasks. Skipped without dask.distributed
(.ci/run installs it)."""

import os
import subprocess
import sys

import numpy as np
import pytest

import dynray
from conftest import BUNNY, ROOT, dynray_bin

dask_distributed = pytest.importorskip("dask.distributed")
import dynray.distributed as dd  # noqa: E402

N = 2_000_000
CHUNK = 250_000  # 8 tasks per call


@pytest.fixture(scope="module")
def client():
    cluster = dask_distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    )
    c = dask_distributed.Client(cluster)
    yield c
    c.close()
    cluster.close()


@pytest.fixture(scope="module")
def rays(bunny):
    """Origins around the bunny's box (grown to three times its size), each aimed at a
    random point of the box: hits, grazing rays and misses; a tenth with a finite tmax."""
    rng = np.random.default_rng(47)
    lo, hi = (np.array(b, np.float64) for b in bunny.mesh.bounds)
    ext = hi - lo
    o = rng.uniform(lo - ext, hi + ext, (N, 3))
    target = rng.uniform(lo, hi, (N, 3))
    r = np.zeros((N, 8), np.float32)
    r[:, :3], r[:, 3:6], r[:, 7] = o, target - o, np.inf
    r[::10, 7] = rng.uniform(0.2, 1.2, len(r[::10]))
    return r


@pytest.fixture(scope="module")
def files(rays, tmp_path_factory):
    d = tmp_path_factory.mktemp("dist")
    np.save(d / "rays.npy", rays)
    return d


@pytest.fixture(scope="module")
def one_process(bunny, rays):
    s = dynray.build(bunny.mesh, "bvh")
    return s.intersect(rays), s.occluded(rays)


def assert_same_hits(got, want):
    assert sorted(got) == ["prim", "t", "u", "v"]
    for k in ("t", "u", "v"):
        assert got[k].dtype == np.float32 and np.array_equal(got[k].view(np.uint32), want[k].view(np.uint32)), k
    assert got["prim"].dtype == np.int64 and np.array_equal(got["prim"], want["prim"])


def test_closest_hits_from_a_path_and_from_memory_equal_one_process(client, rays, files, one_process):
    want, _ = one_process
    assert (want["prim"] >= 0).sum() > N // 4, "the rays should hit the bunny often"
    from_path = dd.trace_rays(BUNNY, files / "rays.npy", client=client, chunk_rows=CHUNK)
    assert_same_hits(from_path, want)
    from_memory = dd.trace_rays(BUNNY, rays, client=client, chunk_rows=CHUNK)
    assert_same_hits(from_memory, want)


def test_occluded_equals_one_process(client, rays, files, one_process):
    _, want = one_process
    got = dd.trace_rays(BUNNY, files / "rays.npy", client=client, occluded=True, chunk_rows=CHUNK)
    assert got.dtype == np.bool_ and np.array_equal(got, want)
    got = dd.trace_rays(BUNNY, rays, client=client, occluded=True, chunk_rows=CHUNK)
    assert np.array_equal(got, want)


def test_float64_fortran_ray_files_are_read_by_rows(client, rays, files, one_process):
    """Memory-mapped float64 in Fortran order (a row slice is strided): the same hits."""
    n = 300_000
    np.save(files / "rays64f.npy", np.asfortranarray(rays[:n].astype(np.float64)))
    got = dd.trace_rays(BUNNY, files / "rays64f.npy", client=client, chunk_rows=70_000)
    assert_same_hits(got, {k: v[:n] for k, v in one_process[0].items()})


@pytest.mark.parametrize("occluded", [False, True])
def test_out_path_writes_the_archive_trace_rays_writes(client, rays, files, occluded):
    tag = "occ" if occluded else "hits"
    out = files / f"dist-{tag}.npz"
    summary = dd.trace_rays(BUNNY, rays, out, client=client, occluded=occluded, chunk_rows=CHUNK)
    assert summary["parts"] == N // CHUNK and summary["rays"] == N
    assert not [p for p in os.listdir(files) if ".parts-" in p], "the parts are removed"
    # The in-process trace-rays job, and the binary when there is one: the same bytes.
    want = [files / f"job-{tag}.npz"]
    dynray.trace_rays(BUNNY, files / "rays.npy", want[0], occluded=occluded)
    exe = dynray_bin()
    if exe is not None:
        want.append(files / f"cli-{tag}.npz")
        args = [str(exe), "trace-rays", str(BUNNY), "--rays", str(files / "rays.npy"), "-o", str(want[1])]
        run = subprocess.run(args + (["--occluded"] if occluded else []), capture_output=True, text=True)
        assert run.returncode == 0, run.stderr
    got = np.load(out)
    for w in want:
        ref = np.load(w)
        assert got.files == ref.files
        for f in ref.files:
            assert got[f].dtype == ref[f].dtype and got[f].tobytes() == ref[f].tobytes(), (w, f)
        assert out.read_bytes() == w.read_bytes(), w


def test_each_worker_process_loads_and_builds_once(client, rays, files, one_process):
    client.run(dd.clear_cache)
    dd.trace_rays(BUNNY, files / "rays.npy", client=client, chunk_rows=CHUNK)
    dd.trace_rays(BUNNY, rays, client=client, occluded=True, chunk_rows=CHUNK)
    info = client.run(dd.cache_info)
    assert len(info) == 2 and len({i["pid"] for i in info.values()}) == 2, info
    assert sum(i["tasks"] for i in info.values()) == 2 * N // CHUNK, info
    for worker, i in info.items():
        assert i["builds"] == i["loads"] == (1 if i["tasks"] else 0), (worker, i)
    # Another structure is another key: built once more where its tasks ran.
    got = dd.trace_rays(BUNNY, rays[:1000], client=client, accel="bih", chunk_rows=250)
    assert_same_hits(got, {k: v[:1000] for k, v in one_process[0].items()})
    after = client.run(dd.cache_info)
    new = sum(after[w]["builds"] - info[w]["builds"] for w in info)
    assert 1 <= new <= 2 and sum(len(i["cached"]) for i in after.values()) == sum(i["builds"] for i in after.values())


def test_an_instant_of_a_physics_scene_is_the_one_trace_rays_traces(client, tmp_path):
    """time= poses the scene (physics simulated) on the workers as trace-rays --time does."""
    physics = ROOT / "examples" / "physics" / "bunny_drop.scn"
    xs, zs = np.meshgrid(np.linspace(-0.9, 0.9, 24), np.linspace(-0.9, 0.9, 24))
    r = np.zeros((xs.size, 8), np.float32)
    r[:, 0], r[:, 1], r[:, 2], r[:, 4], r[:, 7] = xs.ravel(), 4.0, zs.ravel(), -1.0, np.inf
    np.save(tmp_path / "rays.npy", r)
    dynray.trace_rays(physics, tmp_path / "rays.npy", tmp_path / "job.npz", time=0.5)
    want = np.load(tmp_path / "job.npz")
    got = dd.trace_rays(physics, tmp_path / "rays.npy", client=client, time=0.5, chunk_rows=100)
    assert np.count_nonzero(got["prim"] >= 0) > 50
    assert_same_hits(got, {k: want[k] for k in want.files})
    at_zero = dd.trace_rays(physics, r, client=client, chunk_rows=100)
    assert not np.array_equal(at_zero["t"], got["t"]), "the bunny has fallen by 0.5 s"


def test_a_bad_ray_is_named_by_its_row_in_the_batch(client, rays):
    bad = rays[:5000].copy()
    bad[3456, 1] = np.nan
    with pytest.raises(ValueError, match="rays: ray 3456 has a non-finite"):
        dd.trace_rays(BUNNY, bad, client=client, chunk_rows=1000)
    with pytest.raises(ValueError, match=r"shape \(N, 8\)"):
        dd.trace_rays(BUNNY, rays[:, :6], client=client)


def test_importing_the_module_does_not_import_dask():
    code = "import sys, dynray, dynray.distributed; assert 'dask' not in sys.modules and 'distributed' not in sys.modules"
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=os.path.dirname(BUNNY))
    assert run.returncode == 0, run.stderr
