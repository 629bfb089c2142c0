"""Statistics of Mitsuba 3 renders for crates/render/tests/mitsuba_reference.rs.

usage: python3 mitsuba_stats.py OUT.json NAME=SCENE.xml[:max_depth] ...  (needs `pip install mitsuba`)

For each scene: two renders with independent sampler seeds (1 and 2) at SPP samples per
pixel each, `scalar_rgb` variant (as shared/reference), the film's reconstruction filter
replaced by a box filter (dynray box-filters; the Cornell box XML asks for a Gaussian).
Written per scene: the mean image's per-channel mean, its 8x8 tile means (row-major from
the top-left), each tile mean's standard error (from the two renders' per-pixel
differences: var of their average = (a - b)^2 / 4), the render time of one spp, and the
settings. Only these numbers are kept: no image is stored in the repository.
"""
import json, os, sys, time
import numpy as np
import mitsuba as mi

mi.set_variant('scalar_rgb')
SPP = int(os.environ.get('SPP', '512'))


def render(xml, depth, seed):
    folder = os.path.dirname(os.path.abspath(xml))
    mi.Thread.thread().file_resolver().prepend(folder)
    text = open(xml).read().replace('<rfilter type="gaussian"/>', '<rfilter type="box"/>')
    params = {'spp': str(SPP)}
    if depth is not None:
        params['max_depth'] = str(depth)
    scene = mi.load_string(text, **params)
    t0 = time.time()
    img = mi.render(scene, seed=seed, spp=SPP)
    secs = time.time() - t0
    return np.array(img, dtype=np.float64)[:, :, :3], secs


def stats(a, b):
    m = 0.5 * (a + b)
    h, w, _ = m.shape
    th, tw = h // 8, w // 8
    tiles, errs = [], []
    for ty in range(8):
        row, erow = [], []
        for tx in range(8):
            sl = (slice(ty * th, (ty + 1) * th), slice(tx * tw, (tx + 1) * tw))
            n = th * tw
            row.append(m[sl].reshape(-1, 3).mean(0).tolist())
            erow.append(np.sqrt(((a[sl] - b[sl]) ** 2 / 4).reshape(-1, 3).sum(0)) / n)
            erow[-1] = erow[-1].tolist()
        tiles.append(row)
        errs.append(erow)
    return dict(width=w, height=h, mean_rgb=m.reshape(-1, 3).mean(0).tolist(), tile_mean_rgb=tiles,
                tile_stderr_rgb=errs,
                rms_pixel_std_rgb=np.sqrt(((a - b) ** 2 / 4).reshape(-1, 3).mean(0)).tolist())


out = {}
for arg in sys.argv[2:]:
    name, spec = arg.split('=', 1)
    xml, _, depth = spec.partition(':')
    depth = int(depth) if depth else None
    a, ta = render(xml, depth, 1)
    b, tb = render(xml, depth, 2)
    s = stats(a, b)
    s.update(file=os.path.basename(xml), max_depth=depth, spp=2 * SPP, variant='scalar_rgb', mitsuba=mi.__version__,
             seconds_per_spp=(ta + tb) / (2 * SPP), threads=os.cpu_count())
    out[name] = s
    print(name, s['mean_rgb'], f"{s['seconds_per_spp'] * 1e3:.1f} ms/spp", flush=True)
json.dump(out, open(sys.argv[1], 'w'), indent=1)
