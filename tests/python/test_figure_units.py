"""Issue 31: field units in figures on request (``units="field"``, ``--figure-units field``): RPM, klbf
and kft-lbf on the axes, the data converted with drillpy.units' factors, the files still SI."""
import math

import numpy as np
import pytest
from conftest import run_cli

from drillpy.figures import simulation

LBF = 4.4482216152605  # N (drillpy.units)
FT_LBF = 1.3558179483314004  # N m


def test_severity_plot_in_field_units_draws_rpm():
    fig = simulation.severity_plot(None, [10.0, 20.0], [1.2, 0.1], 15.0, units="field")
    ax = fig.axes[0]
    assert ax.get_xlabel() == "top-drive speed [RPM]"
    np.testing.assert_allclose(ax.lines[0].get_xdata(), [10.0 * 30 / math.pi, 20.0 * 30 / math.pi])
    thr = [ln for ln in ax.lines if ln.get_label().startswith("SS > 0.5 below")]
    assert thr[0].get_label() == f"SS > 0.5 below {15.0 * 30 / math.pi:.1f} RPM"
    si = simulation.severity_plot(None, [10.0, 20.0], [1.2, 0.1], 15.0)  # the default stays rad/s
    assert si.axes[0].get_xlabel() == "top-drive speed [rad/s]"
    np.testing.assert_array_equal(si.axes[0].lines[0].get_xdata(), [10.0, 20.0])


def test_time_series_plot_in_field_units_draws_rpm_and_kft_lbf():
    t = np.linspace(0.0, 1.0, 5)
    fig = simulation.time_series_plot(None, t, np.full(5, 10.0), np.full(5, 8000.0), np.full(5, 12.0), units="field")
    a1, a2 = fig.axes
    assert a1.get_ylabel() == "speed [RPM]" and a2.get_ylabel() == "torque on bit [kft-lbf]"
    np.testing.assert_allclose(a1.lines[0].get_ydata(), 10.0 * 30 / math.pi)
    np.testing.assert_allclose(a1.lines[1].get_ydata(), 12.0 * 30 / math.pi)
    np.testing.assert_allclose(a2.lines[0].get_ydata(), 8000.0 / (1e3 * FT_LBF))


def test_stability_map_in_field_units_draws_klbf():
    m = np.array([[1.0, 0.2], [1.1, 0.3]])
    fig = simulation.stability_map_plot(None, [60.0, 120.0], [200.0, 250.0], {"law": m}, units="field")
    ax = fig.axes[0]
    assert ax.get_ylabel() == "weight on bit [klbf]" and ax.get_xlabel() == "top-drive speed [RPM]"
    lo, hi = ax.get_ylim()  # cells centred on the WOBs in klbf
    assert lo < 200e3 / (1e3 * LBF) < 250e3 / (1e3 * LBF) < hi < 100.0
    assert simulation.stability_map_plot(None, [60.0, 120.0], [200.0, 250.0], {"law": m}).axes[0].get_ylabel() == \
        "weight on bit [kN]"


def test_an_unknown_figure_unit_is_refused():
    with pytest.raises(ValueError, match="units = 'imperial': use one of si, field"):
        simulation.severity_plot(None, [10.0, 20.0], [1.2, 0.1], units="imperial")


def test_simulate_writes_its_figure_in_field_units_and_its_data_in_si(tmp_path):
    r = run_cli("simulate", "--preset", "thesis-rig", "--duration", "2", "--transient", "1", "--out",
                str(tmp_path / "f"), "--figure-units", "field")
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "f" / "time_series.png").stat().st_size > 1000
    assert "bit_speed_rad_s" in (tmp_path / "f" / "series.csv").read_text()
    r = run_cli("simulate", "--preset", "thesis-rig", "--figure-units", "imperial", "--out", str(tmp_path / "g"))
    assert r.returncode == 2 and "--figure-units" in r.stderr and "imperial" in r.stderr
    assert not (tmp_path / "g").exists()


@pytest.mark.parametrize("command, grid, figure", [
    ("sweep", ["--speeds", "4,12"], "severity_vs_top_speed.png"),
    ("map", ["--speeds-rpm", "40,110", "--wobs-kn", "0.4,0.6"], "stability_map.png")])
def test_sweep_and_map_take_figure_units(tmp_path, command, grid, figure):
    r = run_cli(command, "--preset", "thesis-rig", *grid, "--out", str(tmp_path / command), "--figure-units", "field",
                "--no-progress")
    assert r.returncode == 0, r.stderr
    assert (tmp_path / command / figure).stat().st_size > 1000
