"""The Python package and the command line run the same engine jobs (issue 41): a
physics scene at a time past the drop, a scene with a distance field beside a mesh, and
the path tracer's depth count give exactly the linear radiance `dynray render -o x.exr`
writes, and `trace_rays(time=…)` traces the simulated frame as `trace-rays --time` does."""

import subprocess

import numpy as np
import pytest

import dynray
from conftest import BUNNY, ROOT, dynray_bin

PHYSICS = ROOT / "examples" / "physics" / "bunny_drop.scn"
# The bunny falls 0.4 m: it touches the floor after about 0.29 s.
PAST_THE_DROP = "0.5"


def cli():
    exe = dynray_bin()
    if exe is None:
        pytest.skip("no dynray binary: set DYNRAY_BIN or cargo build")
    return exe


def run(args):
    done = subprocess.run([str(cli())] + [str(a) for a in args], capture_output=True, text=True, cwd=ROOT)
    assert done.returncode == 0, done.stderr
    return done


def read_exr(path):
    """The (H, W, 3) float32 RGB of an EXR the CLI wrote (OpenEXR's Python bindings)."""
    openexr = pytest.importorskip("OpenEXR", reason="pip install OpenEXR reads the CLI's EXR files")
    with openexr.File(str(path)) as f:
        channels = f.channels()
        if "RGB" in channels:
            rgb = channels["RGB"].pixels
        else:
            rgb = np.stack([channels[c].pixels for c in "RGB"], axis=-1)
    return np.asarray(rgb, dtype=np.float32)


def same_bits(a, b):
    assert a.shape == b.shape, (a.shape, b.shape)
    # NaN-safe bit equality: the film's values, not "close".
    diff = np.count_nonzero(a.view(np.uint32) != b.view(np.uint32))
    assert diff == 0, f"{diff} of {a.size} values differ (max |d| {np.nanmax(np.abs(a - b))})"


def cli_render(tmp_path, scene, *args):
    out = tmp_path / "cli.exr"
    run(["render", scene, "-o", out, *args])
    return read_exr(out)


def test_a_physics_scene_at_a_time_renders_as_on_the_command_line(tmp_path):
    if not BUNNY.exists():
        pytest.skip(f"{BUNNY} is missing")
    want = cli_render(tmp_path, PHYSICS, "--time", PAST_THE_DROP, "--width", "48", "--height", "36", "--spp", "2")
    got = dynray.render(PHYSICS, 48, 36, 2, time=float(PAST_THE_DROP))
    same_bits(got, want)
    # The instant matters: frame 0 has the bunny in the air.
    assert not np.array_equal(got, dynray.render(PHYSICS, 48, 36, 2))
    # A loaded Scene poses and simulates the same way.
    same_bits(dynray.render(dynray.load(PHYSICS), 48, 36, 2, time=float(PAST_THE_DROP)), want)


def test_a_scene_with_a_distance_field_renders_as_on_the_command_line(tmp_path, small_mesh):
    np.savez(tmp_path / "m.npz", vertices=small_mesh.vertices, faces=small_mesh.faces.astype(np.int64))
    run(["adf", "build", tmp_path / "m.npz", "-o", tmp_path / "m.adf", "--max-level", "5"])
    scn = tmp_path / "both.scn"
    scn.write_text('settings { image_width 40 image_height 30 }\n'
                   'camera { perspective position <0, 0.1, 0.5> to <0, 0.1, 0> up <0, 1, 0> angle 40 }\n'
                   'light { position <0, 1, 2> color rgb(1, 1, 1) falloff 0 }\n'
                   'mesh { file "m.npz" }\n'
                   'adf { file "m.adf" material { color rgb(0.9, 0.3, 0.2) } '
                   'transform { translate <0.05, 0, 0> } }\n')
    want = cli_render(tmp_path, scn, "--spp", "1")
    got = dynray.render(scn, spp=1)
    same_bits(got, want)
    # The field is drawn: without its block the image differs.
    plain = tmp_path / "plain.scn"
    plain.write_text("\n".join(scn.read_text().splitlines()[:4]) + "\n")
    assert not np.array_equal(got, dynray.render(plain, spp=1))


def test_the_path_tracers_max_depth_counts_as_on_the_command_line(tmp_path):
    scene = ROOT / "examples" / "whitted.scn"
    want = cli_render(tmp_path, scene, "--integrator", "path", "--max-depth", "3", "--spp", "2",
                      "--width", "32", "--height", "24")
    got = dynray.render(scene, 32, 24, 2, "path", max_depth=3)
    same_bits(got, want)


def test_trace_rays_at_a_time_simulates_physics(tmp_path):
    if not BUNNY.exists():
        pytest.skip(f"{BUNNY} is missing")
    xs, zs = np.meshgrid(np.linspace(-0.9, 0.9, 24), np.linspace(-0.9, 0.9, 24))
    rays = np.zeros((xs.size, 8), np.float32)
    rays[:, 0], rays[:, 1], rays[:, 2] = xs.ravel(), 4.0, zs.ravel()
    rays[:, 4], rays[:, 7] = -1.0, np.inf
    np.save(tmp_path / "rays.npy", rays)
    run(["trace-rays", PHYSICS, "--rays", tmp_path / "rays.npy", "-o", tmp_path / "cli.npz",
         "--time", PAST_THE_DROP])
    dynray.trace_rays(PHYSICS, tmp_path / "rays.npy", tmp_path / "py.npz", time=float(PAST_THE_DROP))
    dynray.trace_rays(PHYSICS, tmp_path / "rays.npy", tmp_path / "zero.npz")
    cli_hits, py_hits, zero = (np.load(tmp_path / n) for n in ("cli.npz", "py.npz", "zero.npz"))
    assert np.count_nonzero(py_hits["prim"] >= 0) > 50
    for k in ("t", "prim", "u", "v"):
        assert np.array_equal(py_hits[k], cli_hits[k]), k
    # The bunny has fallen: the rays meet it lower, or the floor.
    assert not np.array_equal(py_hits["t"], zero["t"])
