"""dynray.load for every format the engine reads, and dynray.render through the engine's
render entry point."""

import numpy as np
import pytest

import dynray
from conftest import BUNNY, SCENES, dynray_bin

FILES = {
    "ply": BUNNY,
    "ply.gz": SCENES / "dragon" / "dragon_vrip_res4.ply.gz",
    "obj": SCENES / "cornell-box" / "mcguire-obj" / "CornellBox-Original.obj",
    "glb": SCENES / "Duck" / "glTF-Binary" / "Duck.glb",
    "gltf": SCENES / "Duck" / "glTF" / "Duck.gltf",
}


@pytest.mark.parametrize("kind", sorted(FILES))
def test_every_format_loads(kind):
    path = FILES[kind]
    if not path.exists():
        pytest.skip(f"{path} is missing")
    sc = dynray.load(path)
    assert sc.mesh.triangle_count > 0 and sc.materials and sc.lights and sc.camera is not None
    assert str(sc.path) == str(path) and sc.size[0] > 0
    hits = dynray.build(sc.mesh).intersect(np.array(sc.camera["position"], np.float32),
                                             np.array([sc.camera["look_at"]], np.float32) - sc.camera["position"])
    assert hits["prim"].shape == (1,)


def test_npz_and_scn(tmp_path, small_mesh):
    np.savez(tmp_path / "m.npz", vertices=small_mesh.vertices, faces=small_mesh.faces.astype(np.int64))
    m = dynray.load(tmp_path / "m.npz").mesh
    assert np.array_equal(m.vertices, small_mesh.vertices) and np.array_equal(m.faces, small_mesh.faces)
    scn = tmp_path / "s.scn"
    scn.write_text('settings { image_width 64 image_height 32 }\n'
                   'camera { perspective position <0, 0.1, 1> to <0, 0.1, 0> up <0, 1, 0> angle 40 }\n'
                   'light { position <0, 1, 2> color rgb(1, 1, 1) falloff 0 }\n'
                   'mesh { file "m.npz" }\n')
    sc = dynray.load(scn)
    assert sc.mesh.triangle_count == small_mesh.triangle_count and sc.size == (64, 32)
    assert sc.camera["position"] == pytest.approx([0, 0.1, 1]) and sc.camera["fov_y_deg"] == pytest.approx(40)
    assert sc.lights == [{"kind": "point", "position": [0.0, 1.0, 2.0], "falloff": 0, "color": [1.0, 1.0, 1.0]}]
    assert dynray.render(sc).shape == (32, 64, 3)


def test_bunny_triangles_are_the_files_faces(bunny):
    assert bunny.mesh.triangle_count == 69451 and bunny.mesh.vertex_count == 35947
    assert bunny.materials[0]["name"] == "" or isinstance(bunny.materials[0]["name"], str)


def test_render_gives_linear_radiance(bunny):
    img = dynray.render(bunny, 40, 30, 1)
    assert img.shape == (30, 40, 3) and img.dtype == np.float32
    assert np.all(np.isfinite(img)) and img.min() >= 0 and img.max() > 0
    assert np.array_equal(img, dynray.render(BUNNY, 40, 30, 1))  # a path renders the same
    assert np.array_equal(img, dynray.render(bunny, 40, 30, 1, threads=1))  # and on one thread
    assert np.array_equal(img, dynray.render(bunny, 40, 30, 1, accel="kdtree"))  # any structure
    assert not np.array_equal(img, dynray.render(bunny, 40, 30, 1, flat_shading=True))
    aa = dynray.render(bunny, 40, 30, 4, seed=1)
    assert aa.shape == img.shape and not np.array_equal(aa, img)


def read_bmp(path):
    """An uncompressed 24- or 32-bit BMP as (H, W, 3) RGB uint8 (what the CLI writes)."""
    b = path.read_bytes()
    off, w, h, bpp = (int.from_bytes(b[i:i + n], "little", signed=True) for i, n in ((10, 4), (18, 4), (22, 4), (28, 2)))
    px = bpp // 8
    stride = (w * px + 3) // 4 * 4
    rows = np.frombuffer(b[off:off + stride * abs(h)], np.uint8).reshape(abs(h), stride)[:, : w * px]
    img = rows.reshape(abs(h), w, px)[:, :, 2::-1]
    return img[::-1] if h > 0 else img


def test_render_matches_the_cli_image(bunny, tmp_path):
    """The film's values, sRGB-encoded as the engine encodes them, are the CLI's BMP."""
    exe = dynray_bin()
    if exe is None:
        pytest.skip("no dynray binary: set DYNRAY_BIN or cargo build")
    import subprocess

    out = tmp_path / "b.bmp"
    args = [str(exe), "render", str(BUNNY), "-o", str(out), "--width", "40", "--height", "30", "--spp", "1"]
    run = subprocess.run(args, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    cli = read_bmp(out)
    c = np.clip(np.nan_to_num(dynray.render(bunny, 40, 30, 1), nan=0.0), 0, 1)
    s = np.where(c <= np.float32(0.0031308), np.float32(12.92) * c, np.float32(1.055) * c ** np.float32(1 / 2.4) - np.float32(0.055))
    ours = np.clip(s * np.float32(255) + np.float32(0.5), 0, 255).astype(np.uint8)
    assert cli.shape == ours.shape
    assert np.abs(ours.astype(int) - cli.astype(int)).max() <= 1  # powf vs numpy's pow: last bit
    assert (ours == cli).mean() > 0.99
