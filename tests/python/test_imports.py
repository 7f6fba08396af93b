"""``import drillpy`` and ``drillpy --help`` stay light: SciPy and Matplotlib load on first use."""
import subprocess
import sys

import drillpy

HEAVY = ("scipy", "matplotlib", "sklearn")


def _loaded_after(code: str) -> set:
    out = subprocess.run([sys.executable, "-c", code + "\nimport sys\nprint(' '.join(sys.modules))"],
                         capture_output=True, text=True, check=True).stdout.split()
    return {m.split(".")[0] for m in out}


def test_import_loads_no_heavy_package():
    assert not _loaded_after("import drillpy") & set(HEAVY)


def test_help_loads_no_heavy_package():
    code = ("from drillpy.cli import build_parser\n"
            "import contextlib, io\n"
            "with contextlib.redirect_stdout(io.StringIO()), contextlib.suppress(SystemExit):\n"
            "    build_parser().parse_args(['--help'])")
    assert not _loaded_after(code) & set(HEAVY)


def test_every_public_name_resolves():
    for name in drillpy.__all__:
        assert getattr(drillpy, name) is not None, name
    assert drillpy.simulate.__module__ == "drillpy.model.simulation"
