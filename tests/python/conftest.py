"""Shared fixtures: repository paths, the measured record and the drillsim executable."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
SHARED = REPO.parent / "shared"
sys.path.insert(0, str(REPO / "benchmarks"))  # the NumPy reference loop used as an oracle


@pytest.fixture(scope="session")
def repo() -> Path:
    return REPO


@pytest.fixture(scope="session")
def testrig_record() -> Path:
    p = SHARED / "data" / "testrig" / "sample175_0-40s.mat"
    if not p.is_file():
        pytest.skip(f"measured record not found at {p} (../shared beside the repository)")
    return p


@pytest.fixture(scope="session")
def drillsim() -> str:
    """Path of the drillsim executable: $DRILLSIM, then PATH, then the development build."""
    for cand in (os.environ.get("DRILLSIM"), shutil.which("drillsim"),
                 str(REPO / "build" / "dev" / "drillsim"), str(REPO / "build" / "ctest" / "drillsim")):
        if cand and Path(cand).is_file():
            return cand
    pytest.fail("drillsim executable not found (set DRILLSIM or build it)")


def run_cli(*args: str, check: bool = False) -> subprocess.CompletedProcess:
    """Run `python -m drillpy ARGS` in a subprocess with the current environment."""
    return subprocess.run([sys.executable, "-m", "drillpy", *args], capture_output=True, text=True,
                          check=check, env={**os.environ, "PYTHONWARNINGS": "error"})


def outside_loop(folder: Path, make_record, effects: tuple) -> tuple:
    """``drillpy loop`` on a record of an outside simulator (``benchmarks/``, no drillpy code), as a
    user runs it from the ``thesis-rig`` preset at 250 Hz with the candidates ``effects`` only:
    ``make_record(path)`` writes the CSV record; returns (loop.json, evidence.json) as dicts."""
    import json
    from drillpy.loop import LoopOptions
    from drillpy.reports.loop import loop_record
    path = folder / "record.csv"
    make_record(str(path))
    out = folder / "res"
    loop_record(path, out, preset="thesis-rig", options=LoopOptions(rate_hz=250, effects=tuple(effects)),
                log=lambda *a: None)
    return json.loads((out / "loop.json").read_text()), json.loads((out / "evidence.json").read_text())
