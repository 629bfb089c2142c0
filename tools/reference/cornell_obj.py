"""Mitsuba 3 reference for dynray's path tracer on an OBJ/MTL scene with `Ke` lamps.

usage:
  python3 cornell_obj.py render SCENE.obj OUT.json [--width 160 --height 120 --spp 1024
                                                     --firefly-spp 64 --png OUT.png]
  python3 cornell_obj.py fireflies IMAGE.exr [...]   (the firefly fraction of EXRs)

Needs `pip install mitsuba numpy` (3.9.1 was used). Writes the statistics that
crates/render/tests/mitsuba_reference.rs (`obj_cornell_box_*`) compares dynray with.

The Mitsuba scene is built the way dynray reads the OBJ (crates/scene/src/formats/obj.rs),
so that both render the same thing:
- one shape per MTL material (Mitsuba's OBJ reader ignores `usemtl`): the faces that use
  it, fan-triangulated, face normals (the file has no `vn`; dynray's emitters are one-sided
  by winding, Mitsuba's by the face normal, which is the winding's);
- a two-sided `diffuse` BSDF of reflectance `Kd` (dynray maps an MTL material without `Ks`,
  mirror or transparency to a two-sided Lambertian; `Ka`, `Ns`, `Ni` then play no part);
- an `area` emitter of radiance `Ke` on every material with a non-black `Ke`;
- a `constant` emitter of dynray's default environment, rgb(0.05, 0.05, 0.08) (a mesh file
  has no background of its own; rays leaving through the open side see it);
- the `path` integrator at max_depth 11 (dynray: `max_recursion_level` 10, its default, + 1),
  rr_depth 5; the `independent` sampler; a box reconstruction filter (dynray box-filters);
- dynray's default view of a model without a camera (crates/scene/src/default_view.rs):
  for an enclosure open towards +z, head-on from +z at the distance where the bounds'
  front face fills the image with 10 % margin, 45 degree vertical field of view, computed
  for dynray's default 640 x 480 settings (the aspect ratio decides the distance; render
  at the same 4:3 aspect).

Written per scene (as crates/render/tests/data/mitsuba_stats.py does): the mean of two
renders with seeds 1 and 2 at `spp` each, its per-channel mean, 8x8 tile means (row-major
from the top-left), each tile mean's standard error (from the renders' per-pixel
differences), and the firefly fraction of `--firefly-spp` renders with seeds 3, 4 and 5
(one figure per seed), with the definition below.

Firefly fraction (the same definition as `firefly_fraction` in the Rust test): the share
of pixels whose luminance Y = 0.2126 R + 0.7152 G + 0.0722 B exceeds
`FIREFLY_RATIO` x the median of the 9 luminances of its 3x3 neighbourhood (itself
included; the image's edge repeated outwards) by at least `FIREFLY_FLOOR` (so the flat
dark background's noise-free pixels never count).
"""
import argparse
import json
import math
import os
import sys
import tempfile
import time

import numpy as np

FIREFLY_RATIO = 4.0
FIREFLY_FLOOR = 0.05
ENVIRONMENT = (0.05, 0.05, 0.08)
MAX_DEPTH = 11
FOV_Y_DEG = 45.0
SETTINGS_W, SETTINGS_H = 640, 480


def firefly_fraction(img):
    """Share of fireflies in an (H, W, 3) linear image (module docs)."""
    y = img[:, :, 0] * 0.2126 + img[:, :, 1] * 0.7152 + img[:, :, 2] * 0.0722
    p = np.pad(y, 1, mode='edge')
    h, w = y.shape
    stack = np.stack([p[dy:dy + h, dx:dx + w] for dy in range(3) for dx in range(3)])
    med = np.median(stack, axis=0)
    return float(np.mean(y > FIREFLY_RATIO * med + FIREFLY_FLOOR))


def read_obj(path):
    """Vertices and, per material name, triangles (fan-triangulated), in file order."""
    verts, by_mat, mtllibs, mat = [], {}, [], None
    for raw in open(path):
        words = raw.split('#')[0].split()
        if not words:
            continue
        key, args = words[0], words[1:]
        if key == 'v':
            verts.append([float(a) for a in args[:3]])
        elif key == 'usemtl':
            mat = ' '.join(args)
        elif key == 'mtllib':
            mtllibs.append(' '.join(args))
        elif key == 'f':
            idx = []
            for a in args:
                i = int(a.split('/')[0])
                idx.append(i - 1 if i > 0 else len(verts) + i)
            tris = by_mat.setdefault(mat, [])
            for k in range(1, len(idx) - 1):
                tris.append((idx[0], idx[k], idx[k + 1]))
    return np.array(verts, dtype=np.float64), by_mat, mtllibs


def read_mtl(path):
    mats, cur = {}, None
    for raw in open(path):
        words = raw.split('#')[0].split()
        if not words:
            continue
        if words[0] == 'newmtl':
            cur = mats.setdefault(' '.join(words[1:]), {})
        elif cur is not None and words[0] in ('Kd', 'Ke'):
            v = [float(a) for a in words[1:4]]
            cur[words[0]] = v * 3 if len(v) == 1 else v
    return mats


def default_camera(verts, by_mat):
    """dynray's head-on view into the box's open +z side (module docs)."""
    used = sorted({i for tris in by_mat.values() for t in tris for i in t})
    p = verts[used]
    lo, hi = p.min(0), p.max(0)
    c, half = (lo + hi) / 2, (hi - lo) / 2
    aspect = SETTINGS_W / SETTINGS_H
    fit = max(half[1], half[0] / aspect, 1e-3)
    dist = half[2] + fit * 1.1 / math.tan(math.radians(FOV_Y_DEG) / 2)
    return c + np.array([0.0, 0.0, dist]), c


def scene_dict(obj, width, height, tmp):
    import mitsuba as mi
    verts, by_mat, mtllibs = read_obj(obj)
    mats = {}
    for lib in mtllibs:
        mats.update(read_mtl(os.path.join(os.path.dirname(obj), lib)))
    eye, target = default_camera(verts, by_mat)
    d = {
        'type': 'scene',
        'integrator': {'type': 'path', 'max_depth': MAX_DEPTH, 'rr_depth': 5},
        'sensor': {
            'type': 'perspective', 'fov': FOV_Y_DEG, 'fov_axis': 'y',
            'to_world': mi.ScalarTransform4f().look_at(origin=eye.tolist(), target=target.tolist(), up=[0, 1, 0]),
            'sampler': {'type': 'independent'},
            'film': {'type': 'hdrfilm', 'width': width, 'height': height, 'rfilter': {'type': 'box'},
                     'pixel_format': 'rgb'},
        },
        'environment': {'type': 'constant', 'radiance': {'type': 'rgb', 'value': list(ENVIRONMENT)}},
    }
    for k, (name, tris) in enumerate(by_mat.items()):
        m = mats.get(name, {})
        # dynray's default material for faces without one: 0.72 grey (obj.rs, "Materials").
        kd = m.get('Kd', [0.72] * 3)
        path = os.path.join(tmp, f'part{k}.obj')
        with open(path, 'w') as f:
            for v in verts:
                f.write('v %r %r %r\n' % tuple(float(x) for x in v))
            for t in tris:
                f.write(f'f {t[0] + 1} {t[1] + 1} {t[2] + 1}\n')
        shape = {'type': 'obj', 'filename': path, 'face_normals': True,
                 'bsdf': {'type': 'twosided', 'bsdf': {'type': 'diffuse',
                                                       'reflectance': {'type': 'rgb', 'value': kd}}}}
        ke = m.get('Ke')
        if ke is not None and max(ke) > 0:
            shape['emitter'] = {'type': 'area', 'radiance': {'type': 'rgb', 'value': ke}}
        d[f'part{k}_{name}'] = shape
    return d, eye, target


def tile_stats(a, b):
    m = 0.5 * (a + b)
    h, w, _ = m.shape
    th, tw = h // 8, w // 8
    tiles, errs = [], []
    for ty in range(8):
        row, erow = [], []
        for tx in range(8):
            sl = (slice(ty * th, (ty + 1) * th), slice(tx * tw, (tx + 1) * tw))
            row.append(m[sl].reshape(-1, 3).mean(0).tolist())
            erow.append((np.sqrt(((a[sl] - b[sl]) ** 2 / 4).reshape(-1, 3).sum(0)) / (th * tw)).tolist())
        tiles.append(row)
        errs.append(erow)
    return dict(width=w, height=h, mean_rgb=m.reshape(-1, 3).mean(0).tolist(), tile_mean_rgb=tiles,
                tile_stderr_rgb=errs, rms_pixel_std_rgb=np.sqrt(((a - b) ** 2 / 4).reshape(-1, 3).mean(0)).tolist())


def render_cmd(args):
    import mitsuba as mi
    mi.set_variant('scalar_rgb')
    with tempfile.TemporaryDirectory() as tmp:
        d, eye, target = scene_dict(args.obj, args.width, args.height, tmp)
        scene = mi.load_dict(d)

        def render(seed, spp):
            t0 = time.time()
            img = mi.render(scene, seed=seed, spp=spp)
            return np.array(img, dtype=np.float64)[:, :, :3], time.time() - t0

        a, ta = render(1, args.spp)
        b, tb = render(2, args.spp)
        s = tile_stats(a, b)
        flies = []
        for seed in (3, 4, 5):
            img, _ = render(seed, args.firefly_spp)
            flies.append(firefly_fraction(img))
    s.update(file=os.path.basename(args.obj), camera={'position': eye.tolist(), 'look_at': target.tolist(),
                                                      'fov_y_deg': FOV_Y_DEG},
             max_depth=MAX_DEPTH, spp=2 * args.spp, variant='scalar_rgb', mitsuba=mi.__version__,
             seconds_per_spp=(ta + tb) / (2 * args.spp), threads=os.cpu_count(),
             firefly={'spp': args.firefly_spp, 'ratio': FIREFLY_RATIO, 'floor': FIREFLY_FLOOR,
                      'fraction_per_seed': flies})
    out = {}
    if os.path.exists(args.out):
        out = json.load(open(args.out))
    out[args.name] = s
    with open(args.out, 'w') as f:
        json.dump(out, f, indent=1)
        f.write('\n')
    print(args.name, 'mean', s['mean_rgb'], f"{s['seconds_per_spp'] * 1e3:.1f} ms/spp",
          'fireflies at', args.firefly_spp, 'spp:', flies, flush=True)
    if args.png:
        m = 0.5 * (a + b)
        srgb = np.where(m <= 0.0031308, 12.92 * m, 1.055 * np.power(np.clip(m, 0, None), 1 / 2.4) - 0.055)
        mi.Bitmap((np.clip(srgb, 0, 1) * 255 + 0.5).astype(np.uint8)).write(args.png)


def fireflies_cmd(args):
    import mitsuba as mi
    mi.set_variant('scalar_rgb')
    for path in args.images:
        img = np.array(mi.Bitmap(path), dtype=np.float64)[:, :, :3]
        print(f'{path}: {img.shape[1]}x{img.shape[0]}, firefly fraction {100 * firefly_fraction(img):.3f} %')


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    sub = ap.add_subparsers(dest='cmd', required=True)
    r = sub.add_parser('render')
    r.add_argument('obj')
    r.add_argument('out')
    r.add_argument('--name', default='obj_cbox')
    r.add_argument('--width', type=int, default=160)
    r.add_argument('--height', type=int, default=120)
    r.add_argument('--spp', type=int, default=1024, help='per render; two renders are averaged')
    r.add_argument('--firefly-spp', type=int, default=64)
    r.add_argument('--png', help='also write the mean image, sRGB 8-bit')
    r.set_defaults(run=render_cmd)
    f = sub.add_parser('fireflies')
    f.add_argument('images', nargs='+')
    f.set_defaults(run=fireflies_cmd)
    args = ap.parse_args()
    args.run(args)


if __name__ == '__main__':
    sys.exit(main())
