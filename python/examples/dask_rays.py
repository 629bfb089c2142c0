"""Times a ray batch through dynray.distributed on a local Dask cluster against one
process, on the same rays, and checks that the answers are the same (docs/python.md,
"Distributed", has the figures of one run).

    pip install ./python "dask[distributed]"
    python python/examples/dask_rays.py [--rays 10000000] [--workers 2] [--mesh PATH]

Rays: origins uniform in the mesh's box grown by its size on every side, each aimed at a
uniform point of the box (float32, tmax inf), written to a .npy in a temporary folder
(removed at the end). Reported: one process (load, build, trace), the cluster's start, the
first distributed call (each worker loads and builds once), a second call (structures
cached), the same from an in-memory array and with out_path, and the cost of a task
that traces nothing much (10 rays), which is the scheduler's round trip per task.
"""

import argparse
import os
import pathlib
import platform
import shutil
import tempfile
import time

import numpy as np

import dynray
import dynray.distributed as dd


def cpu_name():
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def main():
    here = pathlib.Path(__file__).resolve().parents[2]
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rays", type=int, default=10_000_000)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--chunk-rows", type=int, default=1_000_000)
    ap.add_argument("--repeat", type=int, default=3, help="runs of each timing; the median is printed")
    ap.add_argument("--mesh", default=str(here.parent / "shared" / "scenes" / "bunny" / "bun_zipper.ply"))
    args = ap.parse_args()
    from dask.distributed import Client, LocalCluster

    print(f"{cpu_name()}, {os.cpu_count()} logical CPUs; {args.rays} rays, {args.workers} workers, "
          f"chunks of {args.chunk_rows}")
    tmp = pathlib.Path(tempfile.mkdtemp(prefix="dask-rays-"))
    scene = dynray.load(args.mesh)
    lo, hi = (np.array(b, np.float64) for b in scene.mesh.bounds)
    ext = hi - lo
    rng = np.random.default_rng(10)
    rays = np.zeros((args.rays, 8), np.float32)
    rays[:, :3] = rng.uniform(lo - ext, hi + ext, (args.rays, 3))
    rays[:, 3:6] = rng.uniform(lo, hi, (args.rays, 3)) - rays[:, :3]
    rays[:, 7] = np.inf
    path = tmp / "rays.npy"
    np.save(path, rays)

    def timed(label, f, repeat=args.repeat):
        times = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            out = f()
            times.append(time.perf_counter() - t0)
        times.sort()
        print(f"{label:<52} {times[len(times) // 2]:8.2f} s  (runs: {', '.join(f'{t:.2f}' for t in times)})")
        return out

    t0 = time.perf_counter()
    one = dynray.load(args.mesh)
    t1 = time.perf_counter()
    s = dynray.build(one.mesh, "bvh")
    t2 = time.perf_counter()
    print(f"one process: load {1e3 * (t1 - t0):.0f} ms, build {1e3 * (t2 - t1):.0f} ms")
    want = timed("one process, Structure.intersect", lambda: s.intersect(rays))
    occ = timed("one process, Structure.occluded", lambda: s.occluded(rays))
    timed("one process, from the .npy (np.load + intersect)", lambda: s.intersect(np.load(path)))
    timed("one process, trace_rays file job (.npy -> .npz)", lambda: dynray.trace_rays(args.mesh, path, tmp / "one.npz"))

    cluster = timed(f"LocalCluster start ({args.workers} worker processes)", lambda: LocalCluster(
        n_workers=args.workers, threads_per_worker=1, processes=True, dashboard_address=None), repeat=1)
    client = Client(cluster)
    run = dict(client=client, chunk_rows=args.chunk_rows)
    got = timed("dask, .npy path, first call (load + build)", lambda: dd.trace_rays(args.mesh, path, **run), repeat=1)
    info = client.run(dd.cache_info)
    for w, i in sorted(info.items()):
        print(f"  worker {i['pid']}: {i['tasks']} tasks, load {1e3 * i['load_s']:.0f} ms, "
              f"build {1e3 * i['build_s']:.0f} ms, trace {i['trace_s']:.2f} s")
    got = timed("dask, .npy path, structures cached", lambda: dd.trace_rays(args.mesh, path, **run))
    same = all(np.array_equal(got[k].view(np.uint32) if got[k].dtype == np.float32 else got[k],
                              want[k].view(np.uint32) if want[k].dtype == np.float32 else want[k]) for k in want)
    timed("dask, .npy path, threads=1 per task", lambda: dd.trace_rays(args.mesh, path, threads=1, **run))
    got_occ = timed("dask, .npy path, occluded", lambda: dd.trace_rays(args.mesh, path, occluded=True, **run))
    timed("dask, in-memory array (scattered)", lambda: dd.trace_rays(args.mesh, rays, **run))
    timed("dask, .npy path, out_path (parts + merge)", lambda: dd.trace_rays(args.mesh, path, tmp / "d.npz", **run))
    small = rays[:2000]
    timed("dask, 200 tasks of 10 rays", lambda: dd.trace_rays(args.mesh, small, client=client, chunk_rows=10))
    print("identical to one process:", same and np.array_equal(got_occ, occ)
          and (tmp / "d.npz").read_bytes() == (tmp / "one.npz").read_bytes())
    client.close()
    cluster.close()
    shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
