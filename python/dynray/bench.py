"""Times dynray against Embree 4 (embreex) in one process, on the same rays.

    python -m dynray.bench                         # bunny, 1M rays
    python -m dynray.bench --rays 10000000 --scenes bunny,dragon

For each mesh: build time, then closest-hit and any-hit time on primary-like rays (a
pinhole grid in front of the model) and on random rays (origins in the grown box,
uniform directions), medians of --repeat runs after a warm-up. dynray runs on all cores
and on one thread; embreex traces in its calling thread (it loops rtcIntersect1 over
the rays), so the one-thread column is the per-core comparison. Ratios are embreex time
over dynray time (above 1: dynray is faster). Answers are compared in the same run:
the share of rays where both engines report the same triangle (ties at shared edges
may differ legitimately) is printed. Without embreex, dynray alone is timed and the
comparison is skipped with a message.
"""

import argparse
import os
import pathlib
import sys
import time

import numpy as np

import dynray

NAMED = {
    "bunny": "bunny/bun_zipper.ply",
    "dragon": "dragon/dragon_vrip.ply.gz",
}


def scenes_dir():
    env = os.environ.get("DYNRAY_SCENES")
    if env:
        return pathlib.Path(env)
    here = pathlib.Path(__file__).resolve()
    for up in [pathlib.Path.cwd(), *here.parents]:
        for cand in (up / ".." / "shared" / "scenes", up / "shared" / "scenes"):
            if cand.is_dir():
                return cand.resolve()
    return pathlib.Path("../shared/scenes")


def primary_rays(lo, hi, n):
    """n rays from a pinhole at +z through a square grid covering the model's box."""
    side = int(np.ceil(np.sqrt(n)))
    c, ext = (lo + hi) / 2, (hi - lo).max()
    eye = c + np.array([0, 0, 2.0 * ext])
    g = np.linspace(-0.6 * ext, 0.6 * ext, side)
    x, y = np.meshgrid(g, g[::-1])
    d = np.stack([x.ravel(), y.ravel(), np.full(x.size, c[2] - eye[2])], 1)[:n]
    rays = np.empty((n, 8), np.float32)
    rays[:, :3], rays[:, 3:6], rays[:, 6], rays[:, 7] = eye, d, 0, np.inf
    return rays


def random_rays(lo, hi, n, seed=0):
    rng = np.random.default_rng(seed)
    ext = hi - lo
    rays = np.empty((n, 8), np.float32)
    rays[:, :3] = rng.uniform(lo - ext / 4, hi + ext / 4, (n, 3))
    rays[:, 3:6] = rng.normal(size=(n, 3))
    rays[:, 6], rays[:, 7] = 0, np.inf
    return rays


def median_time(f, repeat):
    f()  # warm-up (page faults, thread start-up, Embree's lazy commit)
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return float(np.median(times))


class Embree:
    """embreex (Embree 4): scene build and the two queries."""

    def __init__(self):
        from embreex import rtcore_scene
        from embreex.mesh_construction import TriangleMesh

        self.rtcs, self.TriangleMesh = rtcore_scene, TriangleMesh

    def build(self, v, f):
        scene = self.rtcs.EmbreeScene()
        self.TriangleMesh(scene, v, f)
        # Embree commits (builds its BVH) on the first query: one ray makes it happen here.
        scene.run(np.zeros((1, 3), np.float32), np.ones((1, 3), np.float32))
        return scene

    @staticmethod
    def closest(scene, o, d):
        return scene.run(o, d, output=1)

    @staticmethod
    def occluded(scene, o, d):
        return scene.run(o, d, query="OCCLUDED")


def main(argv=None):
    p = argparse.ArgumentParser(prog="python -m dynray.bench", description=__doc__.split("\n\n")[0])
    p.add_argument("--rays", type=int, default=1_000_000, help="rays per kind (default 1000000)")
    p.add_argument("--scenes", default="bunny", help="comma-separated: bunny, dragon, or mesh files")
    p.add_argument("--accel", default="bvh", help="dynray structure, as --accel names it (default bvh)")
    p.add_argument("--repeat", type=int, default=3, help="timed runs after one warm-up; medians (default 3)")
    a = p.parse_args(argv)
    try:
        embree = Embree()
    except ImportError as e:
        embree = None
        print(f"embreex is not installed ({e}): timing dynray alone (pip install embreex)")
    # (Not "dynray …" first: docs quote this line, and docs' lines that start so are commands.)
    print(f"python -m dynray.bench, dynray {dynray.__version__}: {os.cpu_count()} cores, {a.rays} rays per kind, "
          f"accel {a.accel}, median of {a.repeat}")
    header = f"{'scene':8} {'rays':8} {'query':8} {'dynray':>10} {'dynray 1T':>10} {'embreex':>10} " \
             f"{'ratio':>7} {'ratio 1T':>8} {'same prim':>9}"
    for name in a.scenes.split(","):
        path = scenes_dir() / NAMED[name] if name in NAMED else pathlib.Path(name)
        mesh = dynray.load(path).mesh
        v, f = mesh.vertices, mesh.faces.astype(np.int32)
        lo, hi = (np.array(b, np.float64) for b in mesh.bounds)
        print(f"\n{name}: {mesh.triangle_count} triangles")
        print(header)
        tb = median_time(lambda: dynray.build(mesh, a.accel), a.repeat)
        tb1 = median_time(lambda: dynray.build(mesh, a.accel, threads=1), a.repeat)
        s = dynray.build(mesh, a.accel)
        if embree:
            te = median_time(lambda: embree.build(v, f), a.repeat)
            scene = embree.build(v, f)
        row(name, "-", "build", tb, tb1, te if embree else None, None)
        for kind, rays in (("primary", primary_rays(lo, hi, a.rays)), ("random", random_rays(lo, hi, a.rays))):
            o, d = np.ascontiguousarray(rays[:, :3]), np.ascontiguousarray(rays[:, 3:6])
            for query in ("closest", "any-hit"):
                if query == "closest":
                    ours = lambda t=None: s.intersect(rays, threads=t)  # noqa: E731
                    theirs = lambda: embree.closest(scene, o, d)  # noqa: E731
                else:
                    ours = lambda t=None: s.occluded(rays, threads=t)  # noqa: E731
                    theirs = lambda: embree.occluded(scene, o, d)  # noqa: E731
                t_all = median_time(ours, a.repeat)
                t_one = median_time(lambda: ours(1), a.repeat)
                t_e = median_time(theirs, a.repeat) if embree else None
                same = None
                if embree:
                    if query == "closest":
                        same = float(np.mean(ours()["prim"] == theirs()["primID"]))
                    else:
                        same = float(np.mean(ours() == (theirs() >= 0)))
                row(name, kind, query, t_all, t_one, t_e, same)
    return 0


def row(scene, kind, query, ours, ours1, theirs, same):
    ms = lambda t: f"{t * 1e3:8.1f}ms" if t is not None else f"{'-':>10}"  # noqa: E731
    ratio = lambda t: f"{theirs / t:6.2f}x" if theirs is not None else f"{'-':>7}"  # noqa: E731
    share = f"{same * 100:8.3f}%" if same is not None else f"{'-':>9}"
    print(f"{scene:8} {kind:8} {query:8} {ms(ours)} {ms(ours1)} {ms(theirs)} {ratio(ours)} {ratio(ours1):>8} {share}")
    sys.stdout.flush()


if __name__ == "__main__":
    sys.exit(main())
