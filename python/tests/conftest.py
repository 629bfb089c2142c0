"""Shared fixtures: the test models in ../shared/scenes, a decimated bunny, ray sets, and
the dynray binary for the CLI comparison (DYNRAY_BIN, or target/{release,debug}/dynray)."""

import os
import pathlib

import numpy as np
import pytest

import dynray

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENES = pathlib.Path(os.environ.get("DYNRAY_SCENES", ROOT.parent / "shared" / "scenes"))
BUNNY = SCENES / "bunny" / "bun_zipper.ply"


def dynray_bin():
    """The CLI binary: $DYNRAY_BIN (set by .ci/run), else a built one in target/."""
    env = os.environ.get("DYNRAY_BIN")
    if env:
        return pathlib.Path(env)
    for profile in ("release", "debug"):
        p = ROOT / "target" / profile / "dynray"
        if p.exists():
            return p
    return None


@pytest.fixture(scope="session")
def bunny():
    if not BUNNY.exists():
        pytest.skip(f"{BUNNY} is missing (the test models live in ../shared/scenes)")
    return dynray.load(BUNNY)


def decimate(vertices, faces, cells):
    """Vertex clustering: vertices snapped to a cells^3 grid, one per occupied cell (their
    mean), faces renumbered and degenerate ones dropped. A real, smaller bunny."""
    lo, hi = vertices.min(0), vertices.max(0)
    key = np.floor((vertices - lo) / (hi - lo) * (cells - 1e-3)).astype(np.int64)
    flat = (key[:, 0] * cells + key[:, 1]) * cells + key[:, 2]
    uniq, remap = np.unique(flat, return_inverse=True)
    remap = remap.reshape(-1)
    v = np.zeros((len(uniq), 3))
    np.add.at(v, remap, vertices)
    v /= np.bincount(remap)[:, None]
    f = remap[faces]
    keep = (f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 0] != f[:, 2])
    return v.astype(np.float32), f[keep].astype(np.int64)


@pytest.fixture(scope="session")
def small_mesh(bunny):
    v, f = decimate(bunny.mesh.vertices, bunny.mesh.faces.astype(np.int64), 24)
    return dynray.Mesh(v, f)


def random_rays(mesh, n, seed):
    """(N, 8) float32: origins in the box grown by half its size, directions uniform."""
    rng = np.random.default_rng(seed)
    lo, hi = (np.array(b, np.float64) for b in mesh.bounds)
    ext = hi - lo
    o = rng.uniform(lo - ext / 2, hi + ext / 2, (n, 3))
    d = rng.normal(size=(n, 3))
    rays = np.zeros((n, 8), np.float32)
    rays[:, :3], rays[:, 3:6], rays[:, 7] = o, d, np.inf
    return rays


def primary_rays(mesh, side):
    """(side^2, 8) float32 rays from a pinhole in front (+z) of the mesh through a grid."""
    lo, hi = (np.array(b, np.float64) for b in mesh.bounds)
    c, ext = (lo + hi) / 2, (hi - lo).max()
    eye = c + np.array([0, 0, 2.5 * ext])
    g = np.linspace(-0.6 * ext, 0.6 * ext, side)
    x, y = np.meshgrid(g, g[::-1])
    target = np.stack([c[0] + x.ravel(), c[1] + y.ravel(), np.full(x.size, c[2])], 1)
    rays = np.zeros((x.size, 8), np.float32)
    rays[:, :3], rays[:, 3:6], rays[:, 7] = eye, target - eye, np.inf
    return rays
