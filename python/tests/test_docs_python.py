"""Every Python block of README.md and docs/*.md runs as pasted (issue 48: the quick start
once failed with a NameError).

The blocks of one document run in order in one namespace, as a reader pasting them into
one session would, in a scratch folder laid out like a checkout: `../shared` beside it,
and the files the blocks name without making them (`bunny.ply`, the two rays of
docs/trace-rays.md as `rays.npy`, their hits as `hits.npz`, which a shell block of that
page writes). A block that needs Dask skips without it."""

import importlib.util
import re

import numpy as np
import pytest

import dynray
from conftest import BUNNY, ROOT, SCENES

BLOCK = re.compile(r"^```python\n(.*?)^```", re.S | re.M)

# Python blocks in the docs today; fewer found means the extraction broke.
AT_LEAST = 5


def documents():
    files = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    return [f for f in files if BLOCK.search(f.read_text(encoding="utf-8"))]


def test_the_docs_hold_python_blocks():
    found = sum(len(BLOCK.findall(f.read_text(encoding="utf-8"))) for f in documents())
    assert found >= AT_LEAST, f"found {found} Python blocks in the docs, expected at least {AT_LEAST}"


@pytest.mark.parametrize("doc", documents(), ids=lambda p: p.name)
def test_python_blocks_run_as_pasted(doc, tmp_path, monkeypatch):
    if not BUNNY.exists():
        pytest.skip(f"{BUNNY} is missing (the test models live in ../shared/scenes)")
    work = tmp_path / "checkout"
    work.mkdir()
    (tmp_path / "shared").symlink_to(SCENES.parent)
    (work / "bunny.ply").symlink_to(BUNNY)
    rays = np.zeros((2, 8), np.float32)
    rays[:, :3] = [0, 0.1, 1]
    rays[:, 3:6] = [0, 0, -1]
    rays[:, 7] = np.inf
    np.save(work / "rays.npy", rays)
    dynray.trace_rays(BUNNY, work / "rays.npy", work / "hits.npz")
    monkeypatch.chdir(work)
    namespace = {"__name__": "__docs__"}
    try:
        for i, code in enumerate(BLOCK.findall(doc.read_text(encoding="utf-8")), 1):
            if "dask" in code and importlib.util.find_spec("distributed") is None:
                pytest.skip(f"{doc.name} block {i} needs Dask: pip install 'dask[distributed]'")
            exec(compile(code, f"{doc.name}, Python block {i}", "exec"), namespace)
    finally:
        # A block may start a Dask cluster, which a reader's session would keep running.
        for value in namespace.values():
            if type(value).__name__ in ("Client", "LocalCluster"):
                value.close()
