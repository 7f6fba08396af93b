"""The public API documents itself: every public function, class and method of every drillpy module
has a docstring, and every argument it takes is described in a numpydoc ``Parameters`` section.

Public means: defined in a drillpy module (not imported into it) under a name without a leading
underscore. A function whose only arguments are ``self``/``cls`` needs a docstring but no
``Parameters`` section.
"""
from __future__ import annotations

import dataclasses
import importlib
import inspect
import pkgutil
import re

import pytest

import drillpy

SKIP_MODULES = {"drillpy.__main__"}


def _modules():
    names = ["drillpy"]
    for m in pkgutil.walk_packages(drillpy.__path__, "drillpy."):
        if m.name.split(".")[-1].startswith("_") or m.name in SKIP_MODULES:
            continue
        names.append(m.name)
    return sorted(names)


def _public(module):
    for name, obj in vars(module).items():
        if name.startswith("_") or getattr(obj, "__module__", None) != module.__name__:
            continue
        if inspect.isfunction(obj):
            yield f"{module.__name__}.{name}", obj
        elif inspect.isclass(obj):
            yield f"{module.__name__}.{name}", obj
            for mname, m in vars(obj).items():
                if mname.startswith("_"):
                    continue
                if isinstance(m, (staticmethod, classmethod)):
                    m = m.__func__
                if inspect.isfunction(m):
                    yield f"{module.__name__}.{name}.{mname}", m


def _documented_arguments(doc: str) -> set:
    """Names listed in the numpydoc Parameters (or Attributes/Other Parameters) sections."""
    names, section = set(), None
    lines = doc.splitlines()
    for i, line in enumerate(lines):
        nxt = lines[i + 1] if i + 1 < len(lines) else ""
        if re.fullmatch(r"\s*-{3,}\s*", nxt):
            section = line.strip()
            continue
        if section in ("Parameters", "Other Parameters", "Attributes", "Keyword Arguments"):
            # a parameter line starts at the section's indentation (getdoc dedents it to column 0);
            # its description is indented below it
            m = re.match(r"^(\*{0,2}[A-Za-z_][\w, *]*?)\s*(:.*)?$", line)
            if m:
                for n in m.group(1).split(","):
                    names.add(n.strip().lstrip("*"))
    return names


def _commented_fields(cls) -> set:
    """Fields documented by a Sphinx ``#:`` comment on their line or the line above."""
    try:
        lines = inspect.getsource(cls).splitlines()
    except (OSError, TypeError):
        return set()
    found = set()
    for i, line in enumerate(lines):
        m = re.match(r"^\s+([A-Za-z_]\w*)\s*:", line)
        if m and ("#:" in line or (i > 0 and lines[i - 1].strip().startswith("#:"))):
            found.add(m.group(1))
    return found


def _arguments(fn) -> list:
    try:
        sig = inspect.signature(fn)
    except (TypeError, ValueError):
        return []
    return [p.name for p in sig.parameters.values() if p.name not in ("self", "cls")]


ITEMS = [(name, obj) for mod in _modules() for name, obj in _public(importlib.import_module(mod))]


@pytest.mark.parametrize("name,obj", ITEMS, ids=[n for n, _ in ITEMS])
def test_public_api_is_documented(name, obj):
    doc = inspect.getdoc(obj)
    assert doc and doc.strip(), f"{name}: no docstring"
    if inspect.isclass(obj):
        if dataclasses.is_dataclass(obj):
            fields = [f.name for f in dataclasses.fields(obj) if not f.name.startswith("_")]
            missing = [f for f in fields if f not in _documented_arguments(doc) and f not in _commented_fields(obj)]
            assert not missing, f"{name}: fields not described in the docstring: {missing}"
        return
    args = _arguments(obj)
    if not args:
        return
    missing = [a for a in args if a not in _documented_arguments(doc)]
    assert not missing, f"{name}: arguments not in a numpydoc Parameters section: {missing}"


def test_the_walk_finds_the_api():
    """The check above is not vacuous: it sees the package's main entry points."""
    names = {n for n, _ in ITEMS}
    for expected in ("drillpy.model.simulation.simulate", "drillpy.uncertainty.montecarlo.stochastic_study",
                     "drillpy.records.io.read_record", "drillpy.loop.run.run_loop", "drillpy.validate.number"):
        assert expected in names
    assert len(ITEMS) > 150
