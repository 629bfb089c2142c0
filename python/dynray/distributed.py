"""Ray batches on a Dask cluster (docs/python.md, "Distributed").

    from distributed import Client
    import dynray.distributed
    client = Client("scheduler:8786")               # or Client(LocalCluster(...))
    hits = dynray.distributed.trace_rays("bunny.ply", "rays.npy", client=client)
    dynray.distributed.trace_rays("bunny.ply", "rays.npy", "hits.npz", client=client)

The rows are split into chunks of ``chunk_rows``; each chunk is one task on a worker.
A worker process loads the mesh with the engine's loader (``dynray.load``, so triangle
numbers are the CLI's) and builds the structure once per (mesh file, its mtime and size,
accel, time, frame), then keeps it for the next tasks (``cache_info`` on a worker says
how often it loaded and built). The answers are the engine's, bit for bit: every ray is
traced independently, so the chunks' answers joined in row order are those of one
``Structure.intersect`` / ``occluded`` over all rows, and the archive written with
``out_path`` is the one ``dynray trace-rays`` writes (joined by ``dynray.merge_hits``).

Dask is imported only when a function here needs it: ``import dynray`` works without
it (``pip install "dask[distributed]"`` to use this module).
"""

import collections
import os
import re
import shutil
import tempfile
import threading
import time as _time

import numpy as np

from . import _dynray

__all__ = ["trace_rays", "cache_info", "clear_cache"]

# Structures kept per worker process: a few (mesh, accel, instant) combinations, the
# least recently used dropped first, so a long-lived worker serving many meshes does
# not hold every structure it ever built.
_CACHE_SIZE = 2
_LOCK = threading.Lock()
_CACHE = collections.OrderedDict()
_STATS = {"loads": 0, "builds": 0, "load_s": 0.0, "build_s": 0.0, "tasks": 0, "trace_s": 0.0}


def cache_info():
    """This process's cache: its pid, structures built, mesh loads, their seconds, tasks
    run and their tracing seconds, and the keys held. On a cluster:
    ``client.run(dynray.distributed.cache_info)`` gives it per worker."""
    with _LOCK:
        info = dict(_STATS)
        info["pid"] = os.getpid()
        info["cached"] = [list(k) for k in _CACHE]
        return info


def clear_cache():
    """Drops this process's structures and zeroes its counters
    (``client.run(dynray.distributed.clear_cache)`` on every worker)."""
    with _LOCK:
        _CACHE.clear()
        for k in _STATS:
            _STATS[k] = 0 if isinstance(_STATS[k], int) else 0.0


def _structure(mesh_path, accel, time, frame):
    """The structure over the mesh at that instant, built once per process and key. The
    key holds the file's mtime and size, so an edited file is read again (files it
    refers to, such as a .scn's includes or an .obj's .mtl, are not watched)."""
    st = os.stat(mesh_path)
    key = (mesh_path, st.st_mtime_ns, st.st_size, accel, time, frame)
    # One lock for the lookup and the build: tasks in other threads of this worker wait
    # for the structure rather than build it twice.
    with _LOCK:
        s = _CACHE.get(key)
        if s is not None:
            _CACHE.move_to_end(key)
            return s
        t0 = _time.perf_counter()
        scene = _dynray.load(mesh_path, time=time, frame=frame)
        t1 = _time.perf_counter()
        s = _dynray.build(scene.mesh, accel)
        t2 = _time.perf_counter()
        _STATS["loads"] += 1
        _STATS["builds"] += 1
        _STATS["load_s"] += t1 - t0
        _STATS["build_s"] += t2 - t1
        _CACHE[key] = s
        while len(_CACHE) > _CACHE_SIZE:
            _CACHE.popitem(last=False)
        return s


def _npy_rows(rays_path):
    """The row count of an (N, 8) ray file, from its header (run where the file is)."""
    a = np.load(rays_path, mmap_mode="r")
    _check_array(a, rays_path)
    return a.shape[0]


def _check_array(a, what):
    """trace-rays' rules for a ray array's shape and dtype (values are checked when traced)."""
    if a.ndim != 2 or a.shape[1] != 8:
        raise ValueError(f"{what}: rays must have shape (N, 8), found {tuple(a.shape)}")
    if a.dtype not in (np.dtype("<f4"), np.dtype("<f8")):
        raise TypeError(f"{what}: rays must be float32 or float64 (little-endian), found {a.dtype}")


def _trace_chunk(mesh_path, accel, time, frame, occluded, threads, rays, start, stop):
    """One task: rows start..stop, from a .npy path (memory-mapped: only these rows are
    read) or from the chunk itself (an array scattered to the worker)."""
    s = _structure(mesh_path, accel, time, frame)
    if isinstance(rays, str):
        where = rays
        chunk = np.load(rays, mmap_mode="r")[start:stop]
    else:
        where, chunk = "rays", rays
    t0 = _time.perf_counter()
    try:
        out = s.occluded(chunk, threads=threads) if occluded else s.intersect(chunk, threads=threads)
    except ValueError as e:
        # Name the row of the whole batch, as trace-rays names the row of its file.
        m = re.match(r"ray (\d+) (.*)", str(e), re.S)
        if m is None:
            raise
        raise ValueError(f"{where}: ray {start + int(m.group(1))} {m.group(2)}") from None
    with _LOCK:
        _STATS["tasks"] += 1
        _STATS["trace_s"] += _time.perf_counter() - t0
    return out


def _write_part(path, result, start, stop, total, occluded):
    """A slice archive as ``trace-rays --rows`` writes it (arrays in its order, then
    ``rows``), under a temporary name renamed into place."""
    arrays = {"occluded": result} if occluded else {k: result[k] for k in ("t", "prim", "u", "v")}
    arrays["rows"] = np.array([start, stop, total], np.int64)
    tmp = path + ".tmp.npz"
    np.savez(tmp, **arrays)
    os.replace(tmp, path)


def trace_rays(
    mesh_path,
    rays,
    out_path=None,
    *,
    client,
    accel="bvh",
    occluded=False,
    chunk_rows=1_000_000,
    time=None,
    frame=None,
    threads=None,
):
    """Traces ``rays`` against the mesh or scene file ``mesh_path`` on the Dask cluster
    of ``client`` (a ``distributed.Client``).

    ``rays``: a ``.npy`` path of an (N, 8) array (float32 or float64, C or Fortran
    order, as ``dynray trace-rays`` reads), memory-mapped by the workers so that each
    task reads only its rows (the path must be readable there), or an (N, 8) array in
    memory, scattered to the workers chunk by chunk. ``chunk_rows`` rows make a task.

    Without ``out_path``: returns what one process's ``Structure.intersect`` returns
    (dict of ``t``, ``prim``, ``u``, ``v``) or, with ``occluded=True``, the bool array
    of ``Structure.occluded``, bit for bit. With ``out_path`` (``.npz``): writes the
    archive ``dynray trace-rays MESH --rays RAYS -o OUT [--occluded]`` writes (the
    client writes each chunk's part beside it and merges them with ``merge_hits``; the
    workers need no access to ``out_path``) and returns the merge's summary.

    ``accel`` is any ``--accel`` value; ``time`` (seconds) or ``frame`` pose an animated
    file as ``trace-rays --time/--frame`` does; ``threads`` is each task's thread count
    (default: rayon's pool, every core of the worker's machine; docs/python.md compares
    1 and 2 threads per task with 2 workers on 2 cores). Each worker process loads and
    builds once per (mesh file, accel, time, frame) and keeps the structure for later
    tasks.
    """
    import distributed  # noqa: F401  (lazy: dynray works without dask)

    if out_path is not None:
        out_path = os.fspath(out_path)
        if not out_path.lower().endswith(".npz"):
            raise ValueError(f"{out_path}: trace_rays writes a .npz archive; name the output *.npz")
    if chunk_rows < 1:
        raise ValueError(f"chunk_rows must be at least 1, got {chunk_rows}")
    mesh_path = os.path.abspath(os.fspath(mesh_path))
    common = (mesh_path, accel, time, frame, occluded, threads)

    if isinstance(rays, (str, os.PathLike)):
        rays = os.path.abspath(os.fspath(rays))
        # The header is read where the tasks will read the file.
        n = client.submit(_npy_rows, rays, pure=False).result()
        bounds = _chunks(n, chunk_rows)
        futures = [client.submit(_trace_chunk, *common, rays, a, b, pure=False) for a, b in bounds]
    else:
        array = np.asarray(rays)
        _check_array(array, "rays")
        n = array.shape[0]
        bounds = _chunks(n, chunk_rows)
        scattered = client.scatter([array[a:b] for a, b in bounds], hash=False)
        futures = [client.submit(_trace_chunk, *common, f, a, b, pure=False) for f, (a, b) in zip(scattered, bounds)]

    if out_path is None:
        results = client.gather(futures)
        if occluded:
            return np.concatenate(results)
        return {k: np.concatenate([r[k] for r in results]) for k in ("t", "prim", "u", "v")}
    return _write_archive(futures, bounds, n, out_path, occluded)


def _chunks(n, chunk_rows):
    """Half-open row ranges of at most chunk_rows rows; one empty range for no rows, so
    an empty batch still writes its (empty) archive."""
    return [(a, min(a + chunk_rows, n)) for a in range(0, n, chunk_rows)] or [(0, 0)]


def _write_archive(futures, bounds, n, out_path, occluded):
    """Each chunk's part written as it arrives (the client holds one chunk's answers at
    a time), then merged in row order into out_path; the parts are removed."""
    from distributed import as_completed

    parts_dir = tempfile.mkdtemp(prefix="." + os.path.basename(out_path) + ".parts-", dir=os.path.dirname(out_path) or ".")
    try:
        index = {f.key: i for i, f in enumerate(futures)}
        paths = []
        for future in as_completed(futures):
            i = index[future.key]
            a, b = bounds[i]
            path = os.path.join(parts_dir, f"part-{i:06d}.npz")
            _write_part(path, future.result(), a, b, n, occluded)
            future.release()
            paths.append(path)
        return _dynray.merge_hits(paths, out_path)
    finally:
        shutil.rmtree(parts_dir, ignore_errors=True)
