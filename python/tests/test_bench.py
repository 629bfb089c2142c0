"""python -m dynray.bench runs, compares with embreex when it is installed (and agrees
with it on nearly every ray), and says so when it is not."""

import importlib.util
import re

import dynray.bench as bench
from conftest import BUNNY


def test_bench_runs_and_agrees_with_embree(capsys, bunny):
    assert bench.main(["--rays", "3000", "--repeat", "1", "--scenes", str(BUNNY)]) == 0
    out = capsys.readouterr().out
    rows = [line for line in out.splitlines() if line.startswith(str(BUNNY)) and "triangles" not in line]
    assert len(rows) == 5, out  # build, then 2 ray kinds x 2 queries
    if importlib.util.find_spec("embreex") is None:
        assert "embreex is not installed" in out
        return
    shares = [float(s) for s in re.findall(r"([\d.]+)%", out)]
    assert len(shares) == 4 and min(shares) > 99.0, out
    assert all(re.search(r"\d+\.\d\dx", r) for r in rows), out
