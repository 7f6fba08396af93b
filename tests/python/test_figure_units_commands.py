"""Issue 31: ``--figure-units`` on every command that draws speeds, WOB or torques (report, mc, mc-merge,
control, robust-ss, analyze, predict, loop; simulate, sweep and map in test_figure_units.py): each passes it
to its plot functions, whose axes then read RPM, klbf, kft-lbf (records: lbf, ft-lbf), SI by default.

Every figure a command draws is recorded by file name (the ``_save`` of each figures module wrapped),
so the labels are read from the very figures the command wrote."""
import json
from pathlib import Path

import numpy as np
import pytest

from drillpy.cli import main
from drillpy.model.config import load_config, with_overrides


@pytest.fixture
def drawn(monkeypatch):
    """File name -> matplotlib Figure of every figure written while the test runs."""
    from drillpy.figures import control, frf, loop, records, simulation, stochastic
    figures = {}
    real = simulation._save

    def save(fig, path):
        out = real(fig, path)
        if path is not None:
            figures[Path(path).name] = fig
        return out
    for module in (simulation, control, frf, loop, records, stochastic):
        monkeypatch.setattr(module, "_save", save)
    return figures


def labels(fig) -> list:
    """Every x and y label of a figure's axes."""
    return [t for ax in fig.axes for t in (ax.get_xlabel(), ax.get_ylabel()) if t]


def run(drawn, *args) -> dict:
    """Run a command in this process; returns the figures it wrote."""
    drawn.clear()
    assert main(list(args)) == 0
    return dict(drawn)


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """A short thesis-field configuration, a synthetic rig record and a rig model for predict."""
    d = tmp_path_factory.mktemp("figure-units")
    (d / "field.json").write_text(json.dumps(with_overrides(load_config(preset="thesis-field"), modes=8,
                                                            duration=30.0, transient=15.0)))
    from drillpy.jsonio import jsonable
    from drillpy.records import rigsim
    from drillpy.records.io import write_csv
    from drillpy.loop.synthetic import synthetic_record
    write_csv(synthetic_record(duration_s=6.0, seed=1), d / "rec.csv")
    model = rigsim.RigModel(load_config(preset="thesis-rig")["law"], 0.3, "constant")
    (d / "model.json").write_text(json.dumps(jsonable(model.to_dict(top_speed=8.0, wob=560.0))))
    return d


def test_report_draws_its_sweep_series_and_maps_in_field_units(drawn, tmp_path):
    args = ["report", "--preset", "thesis-rig", "--duration", "3", "--transient", "1", "--no-progress"]
    si = run(drawn, *args, "--out", str(tmp_path / "si"))
    field = run(drawn, *args, "--out", str(tmp_path / "field"), "--figure-units", "field")
    assert si["severity_vs_top_speed.png"].axes[0].get_xlabel() == "top-drive speed [rad/s]"
    assert field["severity_vs_top_speed.png"].axes[0].get_xlabel() == "top-drive speed [RPM]"
    assert labels(si["time_series.png"]) == ["speed [rad/s]", "time [s]", "torque on bit [N m]"]
    assert labels(field["time_series.png"]) == ["speed [RPM]", "time [s]", "torque on bit [kft-lbf]"]
    summary = json.loads((tmp_path / "field" / "summary.json").read_text())  # the data stay SI
    assert summary["sweep"]["top_speeds_rad_s"] == json.loads((tmp_path / "si" / "summary.json").read_text())[
        "sweep"]["top_speeds_rad_s"]


MC = ["mc", "--preset", "thesis-field", "--modes", "8", "--speeds", "10,16", "--samples", "3", "--warmup", "10",
      "--duration", "20", "--transient", "5", "--no-progress"]


def test_mc_and_mc_merge_draw_speeds_in_rpm_on_request(drawn, tmp_path):
    si = run(drawn, *MC, "--out", str(tmp_path / "si"))
    field = run(drawn, *MC, "--out", str(tmp_path / "field"), "--figure-units", "field")
    assert si["severity_band.png"].axes[1].get_xlabel() == "top-drive speed [rad/s]"
    assert field["severity_band.png"].axes[1].get_xlabel() == "top-drive speed [RPM]"
    np.testing.assert_allclose(field["severity_band.png"].axes[0].lines[0].get_xdata(), [10 * 30 / np.pi,
                                                                                          16 * 30 / np.pi])
    assert "speed [RPM]" in labels(field["deterministic_vs_stochastic.png"])
    assert "torque on bit [kft-lbf]" in labels(field["stochastic_response.png"])
    assert "torque on bit [kN m]" in labels(si["stochastic_response.png"])  # SI: kN m above 1000 N m
    merged = run(drawn, "mc-merge", str(tmp_path / "field"), "--out", str(tmp_path / "merged"), "--figure-units",
                 "field")
    assert merged["severity_band.png"].axes[1].get_xlabel() == "top-drive speed [RPM]"


def test_control_draws_speeds_wob_and_motor_torque_in_field_units(drawn, files, tmp_path):
    args = ["control", "--config", str(files / "field.json"), "--drive-inertia", "2000", "--speeds", "10,24",
            "--wobs-kn", "200,245", "--samples", "2", "--validation-samples", "2", "--grid", "2", "--refine", "0",
            "--bootstrap", "20", "--warmup", "10", "--duration", "20", "--transient", "5", "--controllers",
            "z_torque", "--no-progress"]
    si = run(drawn, *args, "--out", str(tmp_path / "si"))
    field = run(drawn, *args, "--out", str(tmp_path / "field"), "--figure-units", "field")
    assert labels(si["maps.png"])[:2] == ["top speed [rad/s]", "WOB [kN]"]
    assert labels(field["maps.png"])[:2] == ["top speed [RPM]", "WOB [klbf]"]
    assert field["p_vs_speed.png"].axes[0].get_xlabel() == "top speed [RPM]"
    assert labels(si["episode.png"]) == ["bit speed [rad/s]", "top speed [rad/s]", "time [s]",
                                         "motor torque [kN m]"]
    assert labels(field["episode.png"]) == ["bit speed [RPM]", "top speed [RPM]", "time [s]",
                                            "motor torque [kft-lbf]"]


def test_robust_ss_draws_speeds_in_rpm_on_request(drawn, tmp_path):
    args = ["robust-ss", "--preset", "thesis-ch6", "--samples", "2", "--speeds", "8,12", "--duration", "0.1",
            "--transient", "0", "--no-progress"]
    assert run(drawn, *args, "--out", str(tmp_path / "si"))["severity_bands.png"].axes[1].get_xlabel() == \
        "top-drive speed [rad/s]"
    field = run(drawn, *args, "--out", str(tmp_path / "field"), "--figure-units", "field")
    assert field["severity_bands.png"].axes[1].get_xlabel() == "top-drive speed [RPM]"


def test_analyze_draws_torque_and_wob_in_field_units(drawn, files, tmp_path):
    args = ["analyze", str(files / "rec.csv"), "--no-sim", "--folds", "0", "--no-progress"]
    si = run(drawn, *args, "--out", str(tmp_path / "si"))
    field = run(drawn, *args, "--out", str(tmp_path / "field"), "--figure-units", "field")
    assert labels(si["time_series.png"]) == ["speed [RPM]", "torque on bit [N m]", "time [s]", "WOB [N]"]
    assert labels(field["time_series.png"]) == ["speed [RPM]", "torque on bit [ft-lbf]", "time [s]", "WOB [lbf]"]
    assert "torque on bit [ft-lbf]" in labels(field["cycle.png"]) and "WOB [lbf]" in labels(field["cycle.png"])
    assert labels(field["loops.png"])[:2] == ["bit speed [RPM]", "torque on bit [ft-lbf]"]
    assert labels(field["laws.png"]) == ["bit speed [RPM]", "torque on bit [ft-lbf]"]
    si_torque = si["time_series.png"].axes[1].lines[0].get_ydata()
    np.testing.assert_allclose(field["time_series.png"].axes[1].lines[0].get_ydata(), si_torque / 1.3558179483314004)


def test_predict_draws_its_overlay_torque_in_ft_lbf_on_request(drawn, files, tmp_path):
    args = ["predict", str(files / "model.json"), str(files / "rec.csv")]
    assert run(drawn, *args, "--out", str(tmp_path / "si"))["overlay.png"].axes[2].get_ylabel() == \
        "torque on bit [N m]"
    field = run(drawn, *args, "--out", str(tmp_path / "field"), "--figure-units", "field")
    assert field["overlay.png"].axes[2].get_ylabel() == "torque on bit [ft-lbf]"


def test_loop_passes_figure_units_to_its_figures(monkeypatch, tmp_path):
    """``drillpy loop --figure-units field`` reaches loop_figures (the loop itself replaced by a stub: a run
    takes minutes), and loops_plot then draws the torque in ft-lbf."""
    from types import SimpleNamespace

    from drillpy.figures import loop as loop_figs
    from drillpy.reports import loop as report
    seen = []
    monkeypatch.setattr(report, "run_loop", lambda record, cfg, options, log: "result")
    monkeypatch.setattr(report, "write_loop", lambda res, out, files: {})
    monkeypatch.setattr(loop_figs, "loop_figures", lambda res, out, units="si": seen.append(units) or {})
    for extra in ([], ["--figure-units", "field"]):
        assert main(["loop", "rec.csv", "--preset", "thesis-rig", "--out", str(tmp_path / "o"), "--no-progress",
                     *extra]) == 0
    assert seen == ["si", "field"]
    d = SimpleNamespace(is_test=np.array([False, True]), starts=np.array([0, 2]),
                        horizon_samples=np.array([[0, 1], [2, 3]]), v_meas=np.arange(4.0), T_meas=np.arange(4.0) + 1)
    pred = SimpleNamespace(v=np.ones((2, 2)), T=np.full((2, 2), 2.0))
    res = SimpleNamespace(data=d, baseline=pred, final=pred)
    assert loop_figs.loops_plot(None, res).axes[0].get_ylabel() == "torque on bit [N m]"
    fig = loop_figs.loops_plot(None, res, units="field")
    assert fig.axes[0].get_ylabel() == "torque on bit [ft-lbf]"
    np.testing.assert_allclose(fig.axes[0].lines[0].get_ydata(), [3.0 / 1.3558179483314004, 4.0 / 1.3558179483314004])


@pytest.mark.parametrize("command", ["report", "mc", "mc-merge", "control", "robust-ss", "analyze", "predict",
                                     "loop"])
def test_every_figure_command_takes_figure_units(command):
    from drillpy.cli import build_parser
    sub = next(a for a in build_parser()._actions if a.dest == "command")
    opts = {o for a in sub.choices[command]._actions for o in a.option_strings}
    assert "--figure-units" in opts
