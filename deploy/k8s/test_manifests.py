"""deploy/k8s: the Indexed Job manifests are valid Kubernetes (kubernetes-validate, the
published OpenAPI schemas, strict), and their command lines, run here as each pod would
run them (JOB_COMPLETION_INDEX set, /data a temporary folder, the manifest's env), give
one process's frames byte for byte and a complete merge. The Dockerfile builds the binary
the manifests call. Run by .ci/run with the Python package's tests; DYNRAY_BIN names the
binary (default target/debug/dynray)."""

import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

yaml = pytest.importorskip("yaml", reason="PyYAML (pip install kubernetes-validate) reads the manifests")

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
SCENES = Path(os.environ.get("DYNRAY_SCENES", ROOT.parent / "shared" / "scenes"))
BIN = Path(os.environ.get("DYNRAY_BIN", ROOT / "target" / "debug" / "dynray"))
# Small frames: the test checks the command lines, not the rendering.
OPTIONS = "--width 64 --height 48 --spp 1 --frames 0..9"


def load(name):
    with open(HERE / name) as f:
        return yaml.safe_load(f)


def container(job):
    (c,) = job["spec"]["template"]["spec"]["containers"]
    return c


def run_pod(job, data, env_extra):
    """Runs the pod's command as the container would, with /data mapped to `data`."""
    c = container(job)
    assert c["command"][:2] == ["sh", "-c"], c["command"]
    (mount,) = c["volumeMounts"]
    env = {"PATH": f"{BIN.parent}{os.pathsep}{os.environ['PATH']}"}
    for e in c.get("env", []):
        env[e["name"]] = e["value"].replace(mount["mountPath"], str(data))
    env.update(env_extra)
    return subprocess.run(c["command"], env=env, capture_output=True, text=True)


def test_manifests_are_valid_kubernetes():
    validate = pytest.importorskip("kubernetes_validate", reason="pip install kubernetes-validate")
    for name in ["frames-job.yaml", "merge-job.yaml"]:
        for version in ["1.30.0", validate.latest_version()]:
            validate.validate(load(name), version, strict=True)


def test_the_frames_job_is_indexed_and_its_shard_count_is_its_completions():
    job = load("frames-job.yaml")
    spec = job["spec"]
    assert spec["completionMode"] == "Indexed"
    env = {e["name"]: e["value"] for e in container(job)["env"]}
    assert int(env["SHARDS"]) == spec["completions"]
    assert "--resume" in container(job)["command"][2], "a restarted pod must skip its finished frames"
    assert container(load("merge-job.yaml"))["image"] == container(job)["image"]


def test_the_pods_command_lines_give_one_processs_frames(tmp_path):
    if not BIN.is_file():
        pytest.fail(f"{BIN}: build the binary first (cargo build), or set DYNRAY_BIN")
    data = tmp_path / "data"
    shutil.copytree(SCENES / "CesiumMan" / "glTF", data / "scene")
    (data / "scene" / "CesiumMan.gltf").rename(data / "scene" / "scene.gltf")
    job = load("frames-job.yaml")
    n = job["spec"]["completions"]
    for k in range(n):
        r = run_pod(job, data, {"JOB_COMPLETION_INDEX": str(k), "OPTIONS": OPTIONS})
        assert r.returncode == 0, f"pod {k}: {r.stderr}"
    # A pod restarted after finishing renders nothing again.
    r = run_pod(job, data, {"JOB_COMPLETION_INDEX": "3", "OPTIONS": OPTIONS})
    assert r.returncode == 0 and "resuming" in r.stderr, r.stderr

    # The merge is given the frames the pods rendered, as the manifest's comment says.
    r = run_pod(load("merge-job.yaml"), data, {"OPTIONS": "--frames 0..9"})
    assert r.returncode == 0, r.stderr
    assert "10 frames 0..=9 complete; 10 timing rows" in r.stderr, r.stderr

    one = tmp_path / "one"
    cmd = [str(BIN), "animate", str(data / "scene" / "scene.gltf"), "--out", str(one)] + OPTIONS.split()
    subprocess.run(cmd, check=True, capture_output=True)
    for k in range(10):
        name = f"frame_{k:04}.png"
        assert (data / "frames" / name).read_bytes() == (one / name).read_bytes(), name


def test_the_dockerfile_builds_the_binary_the_manifests_call():
    text = (HERE / "Dockerfile").read_text()
    build = re.search(r"^RUN (cargo build [^\n]*)$", text, re.M)
    assert build, "no cargo build step"
    assert "--bin dynray" in build.group(1) and "--release" in build.group(1)
    assert "/src/target/release/dynray /usr/local/bin/dynray" in text
    # The builder's Rust is at least the workspace's rust-version.
    rust = re.search(r"^FROM rust:(\d+)\.(\d+)", text, re.M)
    wanted = re.search(r'^rust-version = "(\d+)\.(\d+)"', (ROOT / "Cargo.toml").read_text(), re.M)
    assert tuple(map(int, rust.groups())) >= tuple(map(int, wanted.groups()))
    # `--locked` needs the lock file in the context; the ignore file keeps target/ out.
    assert (ROOT / "Cargo.lock").is_file()
    ignored = (HERE / "Dockerfile.dockerignore").read_text().split()
    assert "target" in ignored
    for e in ["frames-job.yaml", "merge-job.yaml"]:
        assert "dynray animate" in container(load(e))["command"][2]
