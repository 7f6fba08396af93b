"""The checked-in type stubs of the engine module (python/drillpy/_core.pyi) describe the built module."""
import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import pytest

import drillpy

REPO = Path(__file__).resolve().parents[2]


def test_core_stubs_are_current(tmp_path):
    if importlib.util.find_spec("pybind11_stubgen") is None:
        pytest.skip("pybind11-stubgen is not importable (pip install pybind11-stubgen): cannot regenerate the stubs")
    out = tmp_path / "_core.pyi"
    r = subprocess.run(["bash", str(REPO / "scripts" / "generate-stubs.sh"), str(out)], capture_output=True,
                       text=True, env={**os.environ, "PYTHON": sys.executable,
                                       # the drillpy these tests import: the installed one in CI
                                       "PYTHONPATH": str(Path(drillpy.__file__).resolve().parents[1])})
    assert r.returncode == 0, r.stderr
    checked_in = (REPO / "python" / "drillpy" / "_core.pyi").read_text()
    assert out.read_text() == checked_in, \
        "python/drillpy/_core.pyi is stale: rebuild _core and run scripts/generate-stubs.sh"
