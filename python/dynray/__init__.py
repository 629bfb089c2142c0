"""dynray for Python: ray queries over triangle meshes with every acceleration structure
of the dynray engine, in process (docs/python.md).

    import numpy as np, dynray
    scene = dynray.load("bunny.ply")            # any format the engine reads
    bvh = dynray.build(scene.mesh, "bvh")        # or "bih:max_prims=5", "kdtree", ...
    hits = bvh.intersect(origins, directions)    # dict of numpy arrays: t, prim, u, v
    shadowed = bvh.occluded(origins, directions) # bool array

Every structure returns the same closest hit as brute force, bit for bit; queries
release the GIL and run on all cores (``threads=`` to limit them).

Files as the command line has them: ``trace_rays`` (``dynray trace-rays``, with
``rows=(a, b)`` for a slice) and ``merge_hits`` (``dynray merge-hits``). Ray batches on a
Dask cluster: ``dynray.distributed.trace_rays`` (imported on its own,
``import dynray.distributed``; it needs ``pip install "dask[distributed]"``).
"""

from ._dynray import (
    ACCELS,
    Mesh,
    Scene,
    Structure,
    __version__,
    accel_params,
    build,
    load,
    merge_hits,
    render,
    trace_rays,
)

__all__ = [
    "ACCELS",
    "Mesh",
    "Scene",
    "Structure",
    "__version__",
    "accel_params",
    "build",
    "load",
    "merge_hits",
    "render",
    "trace_rays",
]
