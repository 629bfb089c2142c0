#!/usr/bin/env python3
"""Writes the fuzz targets' seed corpora, fuzz/corpus/<target>/ (docs/fuzzing.md).

Seeds are small on purpose (each under 64 KiB, all under 2 MiB): cut from the test
models in ../shared/scenes and from examples/, or written here, so that every reader's
main paths (each PLY encoding, OBJ with materials and textures, each .npy dtype and
order, glTF JSON and GLB with animation, skins and textures, scene-language includes,
BART includes and keyframes, Mitsuba includes and fragments) are in the corpus from the
start. The committed corpus is this script's output; run it again (from anywhere) after
changing it:

    python3 fuzz/make_corpus.py [--dynray target/release/dynray]

Needs Pillow (the JPEG, BMP and PNG variants) and, for the `.adf` seeds, a dynray
binary (`--dynray`; without one the existing `.adf` seeds are kept).
"""

import argparse
import base64
import gzip
import io
import json
import shutil
import struct
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

FUZZ = Path(__file__).resolve().parent
REPO = FUZZ.parent
SCENES = REPO.parent / "shared" / "scenes"
EXAMPLES = REPO / "examples"
CORPUS = FUZZ / "corpus"
SEP = b"\n@@@ "  # fuzz/src/lib.rs, SEPARATOR
MAX_SEED = 64 * 1024


def bundle(main: bytes, *files) -> bytes:
    """A bundle (fuzz/src/lib.rs): the main file, then `@@@ NAME` sections."""
    out = main
    for name, data in files:
        out += SEP + name.encode() + b"\n" + data
    return out


def head_lines(path: Path, n: int) -> bytes:
    return b"".join(path.read_bytes().splitlines(keepends=True)[:n])


# ---------------------------------------------------------------- meshes

CUBE_V = [(x, y, z) for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)]
CUBE_QUADS = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]


def ply_ascii() -> bytes:
    lines = [
        "ply",
        "format ascii 1.0",
        "comment a unit cube, quads, with normals and an extra element",
        f"element vertex {len(CUBE_V)}",
        "property float x",
        "property float y",
        "property float z",
        "property float nx",
        "property float ny",
        "property float nz",
        "property uchar red",
        f"element face {len(CUBE_QUADS)}",
        "property list uchar int vertex_indices",
        "element edge 1",
        "property int vertex1",
        "property int vertex2",
        "end_header",
    ]
    for x, y, z in CUBE_V:
        lines.append(f"{x} {y} {z} {2*x-1} {2*y-1} {2*z-1} 200")
    for q in CUBE_QUADS:
        lines.append("4 " + " ".join(map(str, q)))
    lines.append("0 1")
    return ("\n".join(lines) + "\n").encode()


def ply_binary(little: bool) -> bytes:
    e = "<" if little else ">"
    fmt = "binary_little_endian" if little else "binary_big_endian"
    head = (
        f"ply\nformat {fmt} 1.0\nelement vertex {len(CUBE_V)}\n"
        "property float x\nproperty float y\nproperty float z\n"
        "property double confidence\n"
        f"element face {len(CUBE_QUADS) * 2}\nproperty uchar flags\n"
        "property list uchar uint vertex_index\nend_header\n"
    ).encode()
    body = b""
    for x, y, z in CUBE_V:
        body += struct.pack(e + "fffd", x, y, z, 0.5)
    for a, b, c, d in CUBE_QUADS:
        body += struct.pack(e + "BBIII", 0, 3, a, b, c)
        body += struct.pack(e + "BBIII", 1, 3, a, c, d)
    return head + body


def ply_bunny_cut() -> bytes:
    """The bunny's header with its first faces and the vertices they use, renumbered."""
    src = (SCENES / "bunny" / "bun_zipper.ply").read_bytes()
    head, body = src.split(b"end_header\n", 1)
    lines = body.splitlines()
    count = lambda what: int([l for l in head.splitlines() if l.startswith(what)][0].split()[2])
    total_v, total_f = count(b"element vertex"), count(b"element face"),
    faces = [[int(i) for i in l.split()[1:]] for l in lines[total_v : total_v + 120]]
    used = sorted({i for f in faces for i in f})
    new = {old: k for k, old in enumerate(used)}
    verts = [lines[i] for i in used]
    face_lines = [b"3 " + b" ".join(b"%d" % new[i] for i in f) for f in faces]
    head = head.replace(b"element vertex %d" % total_v, b"element vertex %d" % len(verts))
    head = head.replace(b"element face %d" % total_f, b"element face %d" % len(faces))
    return head + b"end_header\n" + b"\n".join(verts + face_lines) + b"\n"


OBJ_TEXTURED = b"""# two triangles with uvs, normals and negative indices
mtllib lib.mtl
o quad
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0
vn 0 0 1
g front
usemtl tex
s 1
f 1/1/1 2/2/1 3/3/1
f -4/-4/-1 -2/-2/-1 -1/-1/-1
l 1 2
p 3
usemtl undefined
f 1//1 3//1 4//1 2//1
"""

MTL_TEXTURED = b"""# a textured material, an emitter, and one with every scalar
newmtl tex
Kd 1 1 1
map_Kd -o 0.5 0.5 -s 2 2 -clamp on -mm 0 1 -bm 1 t.ppm
map_Ks spec.png
newmtl light
Ka 0 0 0
Kd 0.78 0.78 0.78
Ke 17 12 4
newmtl white
Ka 0.1 0.1 0.1
Kd 0.725
Ks 0.2 0.2 0.2
Ns 10
Ni 1.5
d 0.9
Tr 0.1
illum 7
Tf 1 1 1
Kd spectral red.rfl
"""


def ppm(w: int, h: int, binary: bool = True) -> bytes:
    px = [((x * 255) // max(w - 1, 1), (y * 255) // max(h - 1, 1), 128) for y in range(h) for x in range(w)]
    if binary:
        return b"P6\n# dynray fuzz seed\n%d %d\n255\n" % (w, h) + bytes(c for p in px for c in p)
    return b"P3\n%d %d\n255\n" % (w, h) + " ".join(str(c) for p in px for c in p).encode() + b"\n"


# ---------------------------------------------------------------- numpy


def npy(arr_bytes: bytes, descr: str, shape, fortran=False) -> bytes:
    header = "{'descr': '%s', 'fortran_order': %s, 'shape': %s, }" % (
        descr,
        "True" if fortran else "False",
        "(" + ", ".join(map(str, shape)) + ("," if len(shape) == 1 else "") + ")",
    )
    pad = 64 - (10 + len(header) + 1) % 64
    header = header + " " * pad + "\n"
    return b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode() + arr_bytes


def cube_arrays(vdt: str, fdt: str, fortran: bool):
    tris = [t for a, b, c, d in CUBE_QUADS for t in ((a, b, c), (a, c, d))]
    verts = CUBE_V
    if fortran:
        vflat = [v[j] for j in range(3) for v in verts]
        fflat = [t[j] for j in range(3) for t in tris]
    else:
        vflat = [c for v in verts for c in v]
        fflat = [i for t in tris for i in t]
    vcode = {"<f4": "f", "<f8": "d"}[vdt]
    fcode = {"<i4": "i", "<i8": "q", "<u4": "I", "<u8": "Q"}[fdt]
    v = npy(struct.pack("<%d%s" % (len(vflat), vcode), *vflat), vdt, (len(verts), 3), fortran)
    f = npy(struct.pack("<%d%s" % (len(fflat), fcode), *fflat), fdt, (len(tris), 3), fortran)
    return v, f


def npz(v: bytes, f: bytes, compressed: bool) -> bytes:
    out = io.BytesIO()
    method = zipfile.ZIP_DEFLATED if compressed else zipfile.ZIP_STORED
    with zipfile.ZipFile(out, "w", method) as z:
        z.writestr("vertices.npy", v)
        z.writestr("faces.npy", f)
    return out.getvalue()


# ---------------------------------------------------------------- glTF


def glb(doc: dict, binary: bytes) -> bytes:
    j = json.dumps(doc, separators=(",", ":")).encode()
    j += b" " * (-len(j) % 4)
    binary += b"\0" * (-len(binary) % 4)
    chunks = struct.pack("<I4s", len(j), b"JSON") + j + struct.pack("<I4s", len(binary), b"BIN\0") + binary
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


def png_bytes(img) -> bytes:
    out = io.BytesIO()
    img.save(out, "PNG")
    return out.getvalue()


def gltf_rich(image_png: bytes):
    """A textured, skinned, animated triangle pair with a light: (document, buffer)."""
    buf = b""
    views = []
    accessors = []

    def add(data: bytes, comp: int, count: int, typ: str, mn=None, mx=None, target=None):
        nonlocal buf
        buf += b"\0" * (-len(buf) % 4)
        view = {"buffer": 0, "byteOffset": len(buf), "byteLength": len(data)}
        if target:
            view["target"] = target
        views.append(view)
        buf += data
        acc = {"bufferView": len(views) - 1, "componentType": comp, "count": count, "type": typ}
        if mn is not None:
            acc["min"], acc["max"] = mn, mx
        accessors.append(acc)
        return len(accessors) - 1

    pos = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
    pos_a = add(struct.pack("<12f", *[c for p in pos for c in p]), 5126, 4, "VEC3", [0, 0, 0], [1, 1, 0], 34962)
    nrm_a = add(struct.pack("<12f", *([0, 0, 1] * 4)), 5126, 4, "VEC3", target=34962)
    uv_a = add(struct.pack("<8H", 0, 65535, 65535, 65535, 65535, 0, 0, 0), 5123, 4, "VEC2", target=34962)
    accessors[uv_a]["normalized"] = True
    joints_a = add(struct.pack("<16B", *([0, 1, 0, 0] * 4)), 5121, 4, "VEC4", target=34962)
    weights_a = add(struct.pack("<16f", *([0.75, 0.25, 0, 0] * 4)), 5126, 4, "VEC4", target=34962)
    idx_a = add(struct.pack("<6H", 0, 1, 2, 0, 2, 3), 5123, 6, "SCALAR", target=34963)
    morph_a = add(struct.pack("<12f", *([0, 0, 0.5] * 4)), 5126, 4, "VEC3", [0, 0, 0.5], [0, 0, 0.5])
    ibm_a = add(struct.pack("<32f", *([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1] * 2)), 5126, 2, "MAT4")
    t_a = add(struct.pack("<3f", 0, 0.5, 1), 5126, 3, "SCALAR", [0], [1])
    tr_a = add(struct.pack("<9f", 0, 0, 0, 0, 1, 0, 0, 0, 0), 5126, 3, "VEC3")
    rot_a = add(struct.pack("<36f", *([0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0] * 3)), 5126, 9, "VEC4")
    w_a = add(struct.pack("<3f", 0, 1, 0), 5126, 3, "SCALAR")
    img_view = len(views)
    buf += b"\0" * (-len(buf) % 4)
    views.append({"buffer": 0, "byteOffset": len(buf), "byteLength": len(image_png)})
    buf += image_png
    doc = {
        "asset": {"version": "2.0", "generator": "dynray fuzz/make_corpus.py"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_texture_transform"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "spot", "color": [1, 0.9, 0.8], "intensity": 20, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}}]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 3, 4]}],
        "nodes": [
            {"name": "root", "children": [1], "translation": [0, 0, -1]},
            {"name": "joint0", "children": [2], "rotation": [0, 0, 0, 1]},
            {"name": "joint1", "translation": [0, 1, 0], "scale": [1, 1, 1]},
            {"name": "skinned", "mesh": 0, "skin": 0, "weights": [0.5]},
            {"name": "lamp", "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 2, 2, 1], "extensions": {"KHR_lights_punctual": {"light": 0}}},
        ],
        "meshes": [{"name": "quad", "weights": [0], "primitives": [{
            "attributes": {"POSITION": pos_a, "NORMAL": nrm_a, "TEXCOORD_0": uv_a, "JOINTS_0": joints_a, "WEIGHTS_0": weights_a},
            "indices": idx_a, "material": 0, "mode": 4, "targets": [{"POSITION": morph_a}]}]}],
        "skins": [{"joints": [1, 2], "inverseBindMatrices": ibm_a, "skeleton": 1}],
        "animations": [{"name": "wave", "samplers": [
            {"input": t_a, "output": tr_a, "interpolation": "LINEAR"},
            {"input": t_a, "output": rot_a, "interpolation": "CUBICSPLINE"},
            {"input": t_a, "output": w_a, "interpolation": "STEP"}],
            "channels": [
                {"sampler": 0, "target": {"node": 2, "path": "translation"}},
                {"sampler": 1, "target": {"node": 1, "path": "rotation"}},
                {"sampler": 2, "target": {"node": 3, "path": "weights"}}]}],
        "materials": [{"name": "textured", "alphaMode": "BLEND", "pbrMetallicRoughness": {
            "baseColorFactor": [1, 0.8, 0.6, 0.9],
            "baseColorTexture": {"index": 0, "texCoord": 0, "extensions": {"KHR_texture_transform": {"offset": [0.1, 0.2], "rotation": 0.3, "scale": [2, 2]}}}}}],
        "textures": [{"sampler": 0, "source": 0}],
        "samplers": [{"magFilter": 9728, "wrapS": 33648, "wrapT": 33071}],
        "images": [{"bufferView": img_view, "mimeType": "image/png"}],
        "bufferViews": views,
        "accessors": accessors,
        "buffers": [{"byteLength": len(buf)}],
    }
    return doc, buf


def gltf_strip_fan() -> dict:
    pos = struct.pack("<15f", 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 2, 0, 0)
    uri = "data:application/octet-stream;base64," + base64.b64encode(pos).decode()
    acc = {"bufferView": 0, "componentType": 5126, "count": 5, "type": "VEC3", "min": [0, 0, 0], "max": [2, 1, 0]}
    return {
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": len(pos), "uri": uri}],
        "bufferViews": [{"buffer": 0, "byteLength": len(pos), "byteStride": 12}],
        "accessors": [acc],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "mode": 5}, {"attributes": {"POSITION": 0}, "mode": 6}, {"attributes": {"POSITION": 0}, "mode": 0}]}],
        "nodes": [{"mesh": 0}],
    }


# ---------------------------------------------------------------- scenes

SCN_INCLUDES = b"""// includes, a mesh file, a texture and keyframes across files
include "defs.scn"
settings { image_width 64 image_height 48 sphere_detail 8 frames 5 frame_rate 4 }
camera { perspective position <0, 1, 5> to <0, 0, 0> up <0, 1, 0> angle 45 }
light { position <2, 4, 3> color rgb(1, 1, 1) }
mesh { file "parts/tri.obj" shading smooth 30 material shiny }
mesh { file "quad.ply" material { color rgb(1, 1, 1) texture "t.ppm" } }
object { ball animate { interpolation smooth key 0 { translate <0, 0, 0> } frame 4 { rotate <0, 1, 0> 90 scale 2 tension 0.5 } } }
"""

SCN_DEFS = b"""define shiny material { color rgb(0.9, 0.2, 0.2) finish { ambient 0.1 diffuse 0.6 specular 0.4 shine 20 } }
define ball sphere { center <0, 0, 0> radius 0.5 material shiny }
define half 0.5
"""


def quad_ply_with_uv() -> bytes:
    return (
        b"ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        b"property float s\nproperty float t\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
        b"0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n4 0 1 2 3\n"
    )


TRI_OBJ = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n"

SCN_INLINE = b"""// inline mesh data with normals, expressions and a transform
define k 2
mesh
{
  vertices { 4 <0, 0, 0> <1, 0, 0> <0, k - 1, 0> <0, 0.5, -1> }
  normals { 2 <0, 0, 1> <1, 1, 1> }
  triangles { 2 <0, 1, 2>/<0, 0, 1> <0, 2, 3> }
  shading auto
  transform { rotate <0, 0, 0> <0, 1, 0> 30 * k scale <1, 1, 1> <2, 2, 2> rotate_z -15 translate <-(1 + 1) / k, 0, 0> }
}
box { center <0, -0.05, 0> orientation <0, 45, 0> scale <8, 0.1, 8> }
"""


def aff_bundle(main: Path, budget: int = 40000, per_file: int = 6000) -> bytes:
    """`main` with the files it includes (recursively, `i level name`) while the whole
    stays under `budget` bytes; a file longer than `per_file` (one large mesh block, which
    cannot be cut) is replaced by a small part of the same kind (a mesh)."""
    files, todo, seen = [], [main.name], set()
    total = 0
    while todo:
        name = todo.pop(0)
        if name in seen or not (main.parent / name).exists():
            continue
        seen.add(name)
        data = (main.parent / name).read_bytes()
        if len(data) > per_file and name != main.name:
            data = AFF_PART
        if total + len(data) > budget:
            continue
        total += len(data)
        files.append((name, data))
        for line in data.splitlines():
            w = line.split()
            if len(w) >= 3 and w[0] == b"i":
                todo.append(w[2].decode())
    return bundle(files[0][1], *files[1:])


AFF_SMALL = b"""% every NFF/AFF command: view, lights, each primitive, static and animated
% transforms with their keys, a textured triangle and mesh, and an include
v
from 0 2 -6
at 0 0 0
up 0 1 0
angle 40
hither 0.1
resolution 64 48
b 0.2 0.3 0.4
am 0.2 0.2 0.2
l 0 5 -5
l 2 5 0 1 0.8 0.6
a 0 2 5
f 1 0 0 0.7 0.3 30 0 1
s 0 0 0 0.5
c 0 0 0 0.3 0 1 0 0.1
p 3
0 0 0
1 0 0
0 1 0
pp 3
0 0 0 0 0 1
1 0 0 0 0 1
0 1 0 0 0 1
fm 0.1 0.1 0.1 0.6 0.6 0.6 0.3 0.3 0.3 20 0 1
tt t.ppm
0 0 0 0 0
1 0 0 1 0
0 1 0 0 1
ttp t.ppm
0 0 1 0 0 1 0 0
1 0 1 0 0 1 1 0
0 1 1 0 0 1 0 1
xs 1 1 1
   0 1 0 45
   2 0 0
{
m
 vertices 4
  0 0 0
  1 0 0
  0 1 0
  1 1 0
 texturecoords 4 t.ppm
  0 0
  1 0
  0 1
  1 1
 triangles 2
  0 1 2  0 1 2
  3 2 1  3 2 1
}
x spin
{
tpa 2
0
0 0 0 0 0 1
1 0 0 0 0 1
0 1 0 0 0 1
2
0 0 0 0 0 1
1 0 0 0 0 1
0 1 1 0 0 1
i 0 part.aff
}
k spin
{
  transl 4
  0 0 0 0 0 0 0
  0.5 0.5 0 0 0 0 0
  1.5 0.5 1 0 0.5 0 -0.5
  2 1 0 0 0 0 0
  rot 4
  0 0 1 0 0 0 0 0
  1 0 1 0 45 0 0 0
  1.5 1 0 0 60 0 0 0
  2 0 1 0 90 0 0 0
  scale 4
  0 1 1 1 0 0 0
  1 1.5 1.5 1.5 0 0 0
  1.5 2 1 2 0 0 0
  2 2 2 2 0 0 0
}
"""

AFF_PART = b"""% an included part: a mesh with normals
m
 vertices 3
  0 0 1
  1 0 1
  0 1 1
 normals 1
  0 0 1
 triangles 1
  0 1 2  0 0 0
"""

XML_SHAPES = b"""<scene version="3.0.0">
    <default name="r" value="0.5"/>
    <integrator type="path"><integer name="max_depth" value="-1"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="45"/>
        <string name="fov_axis" value="x"/>
        <transform name="to_world"><lookat origin="0, 1, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="24"/></film>
        <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
    </sensor>
    <bsdf type="twosided" id="gold">
        <bsdf type="roughconductor"><string name="material" value="Au"/><float name="alpha" value="0.2"/><string name="distribution" value="ggx"/></bsdf>
    </bsdf>
    <bsdf type="dielectric" id="glass"><string name="int_ior" value="bk7"/><float name="ext_ior" value="1.0"/></bsdf>
    <bsdf type="conductor" id="mirror"><rgb name="eta" value="0.2, 0.9, 1.1"/><rgb name="k" value="3.9, 2.4, 2.2"/></bsdf>
    <shape type="sphere"><point name="center" x="0" y="0" z="0"/><float name="radius" value="$r"/><ref id="glass"/></shape>
    <shape type="rectangle">
        <transform name="to_world"><rotate x="1" angle="-90"/><scale value="4"/><translate y="-1"/></transform>
        <bsdf type="diffuse"><spectrum name="reflectance" value="0.5"/></bsdf>
    </shape>
    <shape type="cube">
        <transform name="to_world"><matrix value="0.3 0 0 1  0 0.3 0 0  0 0 0.3 0  0 0 0 1"/></transform>
        <ref id="gold"/>
    </shape>
    <shape type="ply">
        <string name="filename" value="meshes/quad.ply"/>
        <boolean name="face_normals" value="true"/>
        <ref id="mirror"/>
        <emitter type="area"><spectrum name="radiance" value="400:1, 500:2, 600:3, 700:4"/></emitter>
    </shape>
    <emitter type="point"><point name="position" value="0, 3, 0"/><rgb name="intensity" value="10, 10, 10"/></emitter>
    <emitter type="constant"><rgb name="radiance" value="0.1, 0.1, 0.1"/></emitter>
</scene>
"""


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dynray", help="a dynray binary, for the .adf seeds")
    args = ap.parse_args()
    from PIL import Image  # noqa: imported here so --help works without Pillow

    seeds: dict[str, dict[str, bytes]] = {t: {} for t in
        ["ply", "obj", "mtl", "npy", "npz", "gltf", "scn", "aff", "mitsuba", "adf", "image"]}

    # Images: small and in every flavour the decoder meets.
    grad = Image.new("RGB", (8, 6))
    grad.putdata([(x * 32, y * 40, 128) for y in range(6) for x in range(8)])
    tiny_png = png_bytes(grad)
    letter = (EXAMPLES / "letter_f.png").read_bytes()
    img = seeds["image"]
    img["letter_f.png"] = letter
    img["rgb8.png"] = tiny_png
    img["gray_alpha.png"] = png_bytes(grad.convert("LA"))
    img["palette.png"] = png_bytes(grad.convert("P"))
    img["rgb16.png"] = png_bytes(grad.convert("I;16"))
    for name, kw in [("baseline.jpg", {}), ("progressive.jpg", {"progressive": True}), ("gray.jpg", {})]:
        out = io.BytesIO()
        (grad.convert("L") if name == "gray.jpg" else grad).save(out, "JPEG", quality=80, **kw)
        img[name] = out.getvalue()
    out = io.BytesIO()
    grad.save(out, "BMP")
    img["rgb.bmp"] = out.getvalue()
    img["p6.ppm"] = ppm(5, 4)
    img["p3.ppm"] = ppm(3, 2, binary=False)
    img["p5.pgm"] = b"P5 4 2 65535\n" + bytes(range(16))
    img["bart_pavement.ppm"] = (SCENES / "bart/robot/TextureFiles/pavement.ppm").read_bytes()

    # PLY.
    p = seeds["ply"]
    p["cube_ascii.ply"] = ply_ascii()
    p["cube_le.ply"] = ply_binary(True)
    p["cube_be.ply"] = ply_binary(False)
    p["cube_le.ply.gz"] = gzip.compress(ply_binary(True), mtime=0)
    p["bunny_cut.ply"] = ply_bunny_cut()

    # OBJ (+ MTL, texture) and MTL.
    o = seeds["obj"]
    cbox = SCENES / "cornell-box/mcguire-obj"
    o["cornell_box.obj"] = bundle((cbox / "CornellBox-Original.obj").read_bytes(),
                                  ("CornellBox-Original.mtl", (cbox / "CornellBox-Original.mtl").read_bytes()))
    o["textured.obj"] = bundle(OBJ_TEXTURED, ("lib.mtl", MTL_TEXTURED), ("t.ppm", ppm(4, 4)))
    o["plain.obj"] = TRI_OBJ
    m = seeds["mtl"]
    m["cornell_box.mtl"] = (cbox / "CornellBox-Original.mtl").read_bytes()
    m["textured.mtl"] = bundle(MTL_TEXTURED.replace(b"newmtl tex", b"newmtl white2"), ("t.ppm", ppm(4, 4)))
    m["png_texture.mtl"] = bundle(b"newmtl white\nKd 1 1 1\nmap_Kd tex.png\n", ("tex.png", tiny_png))

    # numpy: every accepted dtype and both orders; stored and deflated archives.
    n, y = seeds["npz"], seeds["npy"]
    for vdt, fdt, fortran, compressed in [("<f4", "<i4", False, False), ("<f8", "<i8", True, True),
                                          ("<f4", "<u4", True, False), ("<f8", "<u8", False, True)]:
        v, f = cube_arrays(vdt, fdt, fortran)
        tag = f"{vdt[1:]}_{fdt[1:]}_{'F' if fortran else 'C'}"
        n[f"cube_{tag}{'_deflated' if compressed else ''}.npz"] = npz(v, f, compressed)
        y[f"cube_{tag}.npy"] = bundle(v, ("faces.npy", f))

    # glTF: a rich document as JSON (data URI) and as GLB, the morph cube with its buffer
    # as a bundle file, strips and fans.
    g = seeds["gltf"]
    doc, buf = gltf_rich(tiny_png)
    g["rich.glb"] = glb(doc, buf)
    doc_json = json.loads(json.dumps(doc))
    doc_json["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(buf).decode()
    g["rich_data_uri.gltf"] = json.dumps(doc_json, indent=1).encode()
    doc_file = json.loads(json.dumps(doc))
    doc_file["buffers"][0]["uri"] = "rich%20buffer.bin"
    doc_file["images"] = [{"uri": "img.png"}]
    g["rich_files.gltf"] = bundle(json.dumps(doc_file).encode(), ("rich buffer.bin", buf), ("img.png", tiny_png))
    cube_dir = SCENES / "AnimatedMorphCube/glTF"
    g["morph_cube.gltf"] = bundle((cube_dir / "AnimatedMorphCube.gltf").read_bytes(),
                                  ("AnimatedMorphCube.bin", (cube_dir / "AnimatedMorphCube.bin").read_bytes()))
    g["strip_fan_points.gltf"] = json.dumps(gltf_strip_fan()).encode()

    # Scene language: the examples (mesh files they name replaced by small bundled ones),
    # and bundles exercising includes, mesh files and textures.
    s = seeds["scn"]
    mats = (EXAMPLES / "materials.scn").read_bytes()
    small_ply = ply_ascii()
    for ex in ["animated.scn", "materials.scn", "seed_examples.scn", "whitted.scn"]:
        s[ex] = (EXAMPLES / ex).read_bytes()
    s["textured.scn"] = bundle((EXAMPLES / "textured.scn").read_bytes(), ("letter_f.png", letter))
    s["bunny.scn"] = bundle((EXAMPLES / "bunny.scn").read_bytes().replace(
        b"../../shared/scenes/bunny/bun_zipper.ply", b"bunny.ply"), ("materials.scn", mats), ("bunny.ply", small_ply))
    for ex in sorted((EXAMPLES / "physics").glob("*.scn")):
        text = ex.read_bytes().replace(b"../../../shared/scenes/bunny/bun_zipper.ply", b"bunny.ply")
        text = text.replace(b'"../materials.scn"', b'"materials.scn"')
        s["physics_" + ex.name] = bundle(text, ("materials.scn", mats), ("bunny.ply", small_ply))
    s["includes.scn"] = bundle(SCN_INCLUDES, ("defs.scn", SCN_DEFS), ("parts/tri.obj", TRI_OBJ),
                               ("quad.ply", quad_ply_with_uv()), ("t.ppm", ppm(4, 4)))
    s["inline.scn"] = SCN_INLINE

    # AFF: BART's own files (their first lines where long) with the files they include.
    a = seeds["aff"]
    bart = SCENES / "bart"
    museum = bart / "museum/aff"
    a["museum_main.aff"] = aff_bundle(museum / "museum5.aff", per_file=3000)
    a["robot_main.aff"] = aff_bundle(bart / "robot/aff/Robot.aff", per_file=2000)
    a["robot_finger.aff"] = bundle((bart / "robot/aff/rg1.aff").read_bytes(), ("texturer59.ppm", ppm(4, 4)))
    kitchen = bart / "kitchen/aff"
    a["kitchen_wheel.aff"] = aff_bundle(kitchen / "car_front_wheel_left.aff")
    a["kitchen_floor.aff"] = bundle((kitchen / "floor.aff").read_bytes(), ("floor.ppm", ppm(4, 4)))
    a["kitchen_walls.aff"] = aff_bundle(kitchen / "walls.aff", per_file=3000)
    a["every_command.aff"] = bundle(AFF_SMALL, ("part.aff", AFF_PART), ("t.ppm", ppm(4, 4)))

    # Mitsuba: the Cornell box as shipped (main file, fragments, meshes), and one scene
    # with every shape, BSDF and emitter kind.
    x = seeds["mitsuba"]
    mb = SCENES / "cornell-box/mitsuba-cbox"
    meshes = [("meshes/" + f.name, f.read_bytes()) for f in sorted((mb / "meshes").glob("*.obj"))]
    frags = [("fragments/" + f.name, f.read_bytes()) for f in sorted((mb / "fragments").glob("*.xml"))]
    x["cbox_rgb.xml"] = bundle((mb / "cbox-rgb.xml").read_bytes(), *frags, *meshes)
    x["cbox_spectral.xml"] = bundle((mb / "cbox-spectral.xml").read_bytes(), *frags, *meshes)
    x["cbox.xml"] = bundle((mb / "cbox.xml").read_bytes(), *meshes)
    x["shapes.xml"] = bundle(XML_SHAPES, ("meshes/quad.ply", quad_ply_with_uv()))

    # .adf: fields of a tetrahedron at levels 2 and 3 (level 4 is 55 KiB, and adds
    # nothing the format does not have at 3), built by dynray itself.
    if args.dynray:
        with tempfile.TemporaryDirectory() as tmp:
            mesh = Path(tmp) / "tetra.obj"
            mesh.write_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
            for level in (2, 3):
                out = Path(tmp) / f"tetra_l{level}.adf"
                subprocess.run([args.dynray, "adf", "build", str(mesh), "-o", str(out), "--max-level", str(level),
                                "--threads", "1"], check=True, stdout=subprocess.DEVNULL)
                seeds["adf"][out.name] = out.read_bytes()
    else:
        seeds.pop("adf")
        print("make_corpus.py: no --dynray: the .adf seeds are left as they are", file=sys.stderr)

    total = 0
    for target, files in seeds.items():
        d = CORPUS / target
        shutil.rmtree(d, ignore_errors=True)
        d.mkdir(parents=True)
        for name, data in files.items():
            if len(data) >= MAX_SEED:
                raise SystemExit(f"make_corpus.py: {target}/{name} is {len(data)} bytes, past the 64 KiB a seed may have")
            (d / name).write_bytes(data)
            total += len(data)
    total = sum(f.stat().st_size for f in CORPUS.rglob("*") if f.is_file())
    if total >= 2 << 20:
        raise SystemExit(f"make_corpus.py: the corpus is {total} bytes, past 2 MiB")
    print(f"make_corpus.py: {sum(1 for f in CORPUS.rglob('*') if f.is_file())} seeds, {total} bytes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
