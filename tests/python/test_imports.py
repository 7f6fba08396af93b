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


def _modules_after(code: str) -> set:
    out = subprocess.run([sys.executable, "-c", code + "\nimport sys\nprint(' '.join(sys.modules))"],
                         capture_output=True, text=True, check=True).stdout.split()
    return set(out)


def test_mc_import_path_loads_no_heavy_module():
    # what `drillpy mc` imports before its engine runs (cli/uncertainty.py's cmd_mc): scipy.signal
    # alone took 0.8 s of a 5 s run (issue 33); the figures load matplotlib and scipy.stats when drawn
    code = ("from drillpy.cli import uncertainty\n"
            "from drillpy.jsonio import dumps\n"
            "from drillpy.provenance import provenance\n"
            "from drillpy.reports.stochastic import write_figures, write_summary\n"
            "from drillpy.uncertainty.robust_speed import robust_speed_summary\n"
            "from drillpy.uncertainty import montecarlo, process, robust_speed, structural")
    heavy = ("scipy.signal", "scipy.stats", "scipy.optimize", "scipy.special", "scipy.integrate", "matplotlib")
    loaded = _modules_after(code)
    assert not {m for m in loaded if m.split(".")[0] == "matplotlib" or m.startswith(heavy)}


def test_stored_mc_study_loads_no_xarray_pandas_or_dask(tmp_path):
    # `drillpy mc --out DIR` writes and reads its Zarr store with zarr alone (study/store.py): xarray,
    # the pandas it loads and the dask.array it probes took 1.2 s of a 5 s run's serial start (issue 33)
    code = ("import contextlib, io\n"
            "from drillpy.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            f"    main(['mc', '--preset', 'thesis-field', '--samples', '2', '--speeds', '10:12:2', '--warmup', '1',"
            f" '--duration', '3', '--transient', '1', '--no-figures', '--no-progress', '--out', {str(tmp_path)!r}])")
    loaded = {m.split(".")[0] for m in _modules_after(code)}
    assert (tmp_path / "study.zarr").is_dir() and (tmp_path / "mc.json").is_file()
    assert not loaded & {"xarray", "pandas", "dask"}
