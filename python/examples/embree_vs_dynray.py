"""The same closest-hit query through trimesh + embreex (Embree 4) and through dynray.

    pip install ./python trimesh embreex
    python python/examples/embree_vs_dynray.py ../shared/scenes/bunny/bun_zipper.ply
"""

import sys

import numpy as np
import trimesh

import dynray

path = sys.argv[1] if len(sys.argv) > 1 else "../shared/scenes/bunny/bun_zipper.ply"
tm = trimesh.load(path, process=False)  # keep the file's vertices and faces as they are
rng = np.random.default_rng(0)
origins = rng.uniform(tm.bounds[0], tm.bounds[1], (100_000, 3))
directions = rng.normal(size=(100_000, 3))

# trimesh: its Embree intersector (embreex) when installed.
locations, index_ray, index_tri = tm.ray.intersects_location(origins, directions, multiple_hits=False)
print(f"trimesh/{type(tm.ray).__module__}: {len(index_ray)} hits")

# dynray: the same arrays, a structure of your choice, numpy arrays back.
bvh = dynray.build(dynray.Mesh(tm.vertices, tm.faces), "bvh")
hits = bvh.intersect(origins, directions, point=True)
print(f"dynray {bvh.name}: {(hits['prim'] >= 0).sum()} hits")

agree = hits["prim"][index_ray] == index_tri
print(f"same triangle on {agree.mean() * 100:.3f} % of embree's hits; largest point distance "
      f"{np.abs(hits['point'][index_ray] - locations).max():.2e}")
