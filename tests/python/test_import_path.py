"""The test session imports one drillpy: no test module (nor a benchmark it imports) puts the source
tree before the installed package on sys.path. A Dask worker spawned later inherits sys.path and would
import the other copy (in CI the source tree's, without its compiled engine: the workers die)."""
import sys
from pathlib import Path

import drillpy

REPO = Path(__file__).resolve().parents[2]


def test_the_tests_leave_the_installed_drillpy_first_on_sys_path():
    here = Path(drillpy.__file__).resolve().parent.parent
    tree = (REPO / "python").resolve()
    if here == tree:  # a development run (PYTHONPATH=python): the tree is the package
        return
    on_path = [Path(p).resolve() for p in sys.path if p]
    assert tree not in on_path, f"{tree} is on sys.path while drillpy comes from {here}"
