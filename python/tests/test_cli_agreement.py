"""Python and the command line give the same answers, bit for bit, on the bunny:
Structure.intersect, dynray.trace_rays and `dynray trace-rays` (when the binary is
found: $DYNRAY_BIN or target/*/dynray)."""

import subprocess

import numpy as np
import pytest

import dynray
from conftest import BUNNY, dynray_bin, primary_rays, random_rays

FIELDS = ["t", "prim", "u", "v", "normal", "point"]


def bits(a):
    """The array's bytes, so that NaN == NaN and -0.0 != 0.0: a bitwise comparison."""
    return np.ascontiguousarray(a).view(np.uint8)


@pytest.fixture(scope="module")
def rays(bunny):
    return np.concatenate([primary_rays(bunny.mesh, 100), random_rays(bunny.mesh, 10000, 7)])


@pytest.fixture(scope="module")
def files(rays, tmp_path_factory):
    d = tmp_path_factory.mktemp("cli")
    np.save(d / "rays.npy", rays)
    return d


def test_in_process_equals_trace_rays_file(bunny, rays, files):
    s = dynray.build(bunny.mesh, "bvh")
    got = s.intersect(rays, normal=True, point=True)
    summary = dynray.trace_rays(BUNNY, files / "rays.npy", files / "py.npz", fields=FIELDS)
    assert summary["rays"] == len(rays) and summary["accel"] == "bvh"
    saved = np.load(files / "py.npz")
    assert sorted(saved.files) == sorted(FIELDS)
    for f in FIELDS:
        assert saved[f].dtype == got[f].dtype, f
        assert np.array_equal(bits(saved[f]), bits(got[f])), f
    assert summary["hits"] == int((got["prim"] >= 0).sum()) > 1000


def test_occluded_in_process_equals_file(bunny, rays, files):
    s = dynray.build(bunny.mesh, "bih")
    occ = s.occluded(rays)
    dynray.trace_rays(BUNNY, files / "rays.npy", files / "occ.npz", accel="bih", occluded=True)
    assert np.array_equal(np.load(files / "occ.npz")["occluded"], occ)
    assert np.array_equal(occ, s.intersect(rays)["prim"] >= 0)


@pytest.mark.parametrize("occluded", [False, True])
def test_cli_binary_writes_the_same_archive(rays, files, occluded):
    exe = dynray_bin()
    if exe is None:
        pytest.skip("no dynray binary: set DYNRAY_BIN or cargo build")
    out_cli, out_py = files / f"cli-{occluded}.npz", files / f"py-{occluded}.npz"
    args = [str(exe), "trace-rays", str(BUNNY), "--rays", str(files / "rays.npy"), "-o", str(out_cli)]
    args += ["--occluded"] if occluded else ["--fields", ",".join(FIELDS)]
    run = subprocess.run(args, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    dynray.trace_rays(BUNNY, files / "rays.npy", out_py, occluded=occluded, fields=None if occluded else FIELDS)
    cli, py = np.load(out_cli), np.load(out_py)
    assert cli.files == py.files
    for f in cli.files:
        assert cli[f].dtype == py[f].dtype and np.array_equal(bits(cli[f]), bits(py[f])), f


def test_float64_and_fortran_rays_are_converted_with_a_note(bunny, rays, files):
    np.save(files / "rays64.npy", np.asfortranarray(rays.astype(np.float64)))
    with pytest.warns(UserWarning, match="float64 in Fortran order, converted"):
        dynray.trace_rays(BUNNY, files / "rays64.npy", files / "h64.npz")
    want = dynray.build(bunny.mesh).intersect(rays)
    assert np.array_equal(bits(np.load(files / "h64.npz")["t"]), bits(want["t"]))


def test_row_slices_merge_into_the_full_archive(rays, files):
    """trace_rays(rows=(a, b)) is `trace-rays --rows a..b`; merge_hits is `merge-hits`."""
    n = len(rays)
    full = files / "full-rows.npz"
    dynray.trace_rays(BUNNY, files / "rays.npy", full)
    whole = np.load(full)
    parts = []
    for a, b in [(4000, n), (0, 1234), (1234, 4000)]:
        p = files / f"part-{a}.npz"
        assert dynray.trace_rays(BUNNY, files / "rays.npy", p, rows=(a, b))["rays"] == b - a
        part = np.load(p)
        assert part.files == ["t", "prim", "u", "v", "rows"] and list(part["rows"]) == [a, b, n]
        for k in ("t", "prim", "u", "v"):
            assert np.array_equal(bits(part[k]), bits(whole[k][a:b])), k
        parts.append(p)
    summary = dynray.merge_hits(parts, files / "merged.npz")
    assert (summary["parts"], summary["rays"], summary["arrays"]) == (3, n, ["t", "prim", "u", "v"])
    assert (files / "merged.npz").read_bytes() == full.read_bytes()
    with pytest.raises(ValueError, match="rows 1234..4000 are in no part"):
        dynray.merge_hits(parts[:2], files / "gap.npz")
    with pytest.raises(ValueError, match="the output is one of the parts"):
        dynray.merge_hits(parts, parts[0])
    with pytest.raises(ValueError, match=f"rows 0..{n + 1} reach past the file's {n} rays"):
        dynray.trace_rays(BUNNY, files / "rays.npy", files / "past.npz", rows=(0, n + 1))
    assert not (files / "gap.npz").exists() and not (files / "past.npz").exists()
