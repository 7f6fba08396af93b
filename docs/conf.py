"""Sphinx configuration of drillpy's documentation.

Build (from the repository root, after the engine is built: scripts/dev-build.sh or pip install .):

    python3 -m sphinx -W --keep-going -b html docs docs/_build/html

``-W`` turns every warning into an error, so that a broken example, a bad cross-reference or a
docstring numpydoc cannot parse fails the build (scripts/test.sh runs it). The gallery's examples
(docs/examples/plot_*.py) are executed on every build.
"""
from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
# The working tree's package when its engine is built there (scripts/dev-build.sh), else the
# installed one (scripts/test.sh installs the wheel; a fresh clone has no engine in python/drillpy).
if list((ROOT / "python" / "drillpy").glob("_core*.so")):
    sys.path.insert(0, str(ROOT / "python"))

import drillpy  # noqa: E402

project = "drillpy"
author = "the drillpy developers"
copyright = "2026, the drillpy developers"
release = version = drillpy.__version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "examples/README.rst", "Thumbs.db", ".DS_Store"]
templates_path = []

# MyST: the existing docs/*.md; anchors for their headings so that pages can link to sections.
myst_heading_anchors = 3
myst_enable_extensions = ["dollarmath"]

# API reference: autosummary writes one page per public object (docs/api/ is generated, not kept).
autosummary_generate = True
autosummary_imported_members = False
# "ignore-module-all": a package documents what it defines, not what its __all__ re-exports
# (drillpy.loop re-exports the function `evidence` beside its module `drillpy.loop.evidence`).
autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": False, "ignore-module-all": True}
autodoc_typehints = "none"   # the numpydoc sections already give the types
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "within_subsection_order": "FileNameSortKey",
    "download_all_examples": False,
    "remove_config_comments": True,
    "abort_on_example_error": True,
    "matplotlib_animations": False,
    "min_reported_time": 0,
    "show_memory": False,
}



def _escape_bars(line: str) -> str:
    """``|x|`` in drillpy's docstrings is an absolute value (or a norm), never a reStructuredText
    substitution: escape the bars outside inline literals."""
    parts = line.split("``")
    for i in range(0, len(parts), 2):  # even pieces are outside ``...``
        parts[i] = parts[i].replace("|", "\\|")
    return "``".join(parts)


def _plain_bars(app, what, name, obj, options, lines):
    lines[:] = [_escape_bars(x) for x in lines]


def setup(app):
    app.connect("autodoc-process-docstring", _plain_bars)


html_theme = "alabaster"
html_title = f"drillpy {release}"
html_static_path = []
