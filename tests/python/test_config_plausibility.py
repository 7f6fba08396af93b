"""Issue 31 item 4: absurd configurations warn (field, value, range, source); the API validates like the CLI."""
import copy
import math

import numpy as np
import pytest

import drillpy
from drillpy.cli import main
from drillpy.model.plausibility import ImplausibleConfiguration, check_config

FIELD = drillpy.load_config(preset="thesis-field")


def _with(path, value):
    c = copy.deepcopy(FIELD)
    *head, last = path
    d = c
    for k in head:
        d = d[k]
    d[last] = value
    return c


@pytest.mark.parametrize("preset", ["thesis-field", "thesis-ch4", "thesis-rig", "thesis-ch6"])
def test_the_thesis_strings_are_plausible(preset):
    assert check_config(drillpy.load_config(preset=preset)) == []


@pytest.mark.parametrize("path, value, field, hint", [
    (("string", "sections", 0, "outer_radius_m"), 63.5, "string.sections[0].outer_radius_m", "mm or inches"),
    (("string", "sections", 0, "youngs_modulus_pa"), 207.0, "string.sections[0].youngs_modulus_pa", "GPa typed as Pa"),
    (("string", "sections", 0, "density_kg_m3"), 7.85, "string.sections[0].density_kg_m3", "g/cm^3"),
    (("string", "sections", 0, "length_m"), 1e308, "string.sections[*].length_m (total)", "Kola"),
    (("law", "b0"), -3478.0, "law.b0", "negative one drives the bit"),
    (("operation", "top_speed_rad_s"), 120.0, "operation.top_speed_rad_s", "it is 12.6 rad/s"),
    (("operation", "wob_n"), 245e6, "operation.wob_n", "kN, klbf or kg"),
])
def test_an_absurd_value_is_one_warning_with_its_range_and_source(path, value, field, hint):
    (w,) = check_config(_with(path, value))
    assert w.field == field and w.value == value and not w.plausible[0] <= value <= w.plausible[1]
    assert hint in w.message and w.source in w.message and f"{field} = " in w.message


def test_the_api_warns_and_the_command_prints_each_warning_once(capsys):
    with pytest.warns(ImplausibleConfiguration, match="if 120 was meant in RPM, it is 12.6 rad/s"):
        drillpy.simulate(FIELD, top_speed=120.0, record=False)
    assert main(["simulate", "--preset", "thesis-field", "--top-speed", "120", "--duration", "4",
                 "--transient", "2"]) == 0
    err = capsys.readouterr().err
    assert err.count("drillpy: warning: operation.top_speed_rad_s = 120 rad/s") == 1
    assert main(["simulate", "--preset", "thesis-field", "--top-speed", "120rpm", "--duration", "4",
                 "--transient", "2"]) == 0
    assert "warning" not in capsys.readouterr().err  # the same speed with its unit: nothing to say


def test_the_api_refuses_a_negative_wob_as_the_command_does(capsys):
    with pytest.raises(ValueError) as api:
        drillpy.simulate(FIELD, wob=-150e3, record=False)
    assert main(["simulate", "--preset", "thesis-field", "--wob", "-150kN"]) == 2
    assert str(api.value) == "operation.wob_n = -150000: must not be negative"
    assert capsys.readouterr().err.strip() == f"drillpy: error: {api.value}"


def test_a_threshold_through_nan_is_an_error_naming_it():
    speeds, ss = [10.0, 12.0, 14.0, 16.0], [1.2, math.nan, 0.3, 0.2]
    with pytest.raises(ValueError, match=r"severities\[1\] = nan at 12 rad/s"):
        drillpy.severity_threshold(speeds, ss)
    with pytest.raises(ValueError, match=r"severities\[1\] = nan at 12 rad/s"):
        drillpy.severity_crossings(speeds, ss)
    assert drillpy.severity_threshold(speeds, np.nan_to_num(ss, nan=1.0)) == pytest.approx(12.0 + 2 * 0.5 / 0.7)


def test_pi_without_gains_is_the_tuning_its_help_promises(capsys):
    from drillpy.control.tuning import drive_gains, nominal_pi_gains
    args = ["simulate", "--preset", "thesis-field", "--duration", "10", "--transient", "5", "--drive-inertia", "2000",
            "--json"]
    runs = {}
    for c in ("pi", "stiff"):
        assert main([*args, "--controller", c]) == 0
        runs[c] = capsys.readouterr().out
    assert runs["pi"] == runs["stiff"]  # the stiff drive's pole placement
    g = nominal_pi_gains(FIELD, 2000.0)
    w1 = drive_gains(drillpy.with_overrides(FIELD, top_drive={"type": "controlled", "inertia_kg_m2": 2000.0,
                                                              "controller": {"type": "stiff"}}))["omega1_rad_s"]
    assert g["kp_nms_rad"] == pytest.approx(2 * 2000.0 * 20 * w1) and g["ki_nm_rad"] == pytest.approx(2000.0 * (20 * w1) ** 2)


@pytest.mark.parametrize("option, value, blamed", [("--dt", "1e-12", "a time step below 1 us"),
                                                   ("--duration", "1e300", "a duration over 100 days")])
def test_too_many_steps_names_the_time_step_with_the_duration(capsys, option, value, blamed):
    assert main(["simulate", "--preset", "thesis-rig", option, value]) == 2
    err = capsys.readouterr().err
    assert err.startswith("drillpy: error: simulation.dt_s = ") and "simulation.duration_s = " in err
    assert blamed in err and err.count("\n") == 1


def test_a_record_without_a_stick_phase_is_not_called_stick_slip(tmp_path):
    from drillpy.records.io import Record
    from drillpy.records.analysis import AnalysisOptions, compute_analysis
    run = drillpy.simulate(drillpy.load_config(preset="thesis-rig"), top_speed=20.0)  # SS 0.77, the bit never stops
    assert run.stick_fraction == 0.0 and run.severity > 0.5
    rec = Record(time_s=run.t, bit_speed=run.bit_speed, top_speed=run.top_speed, torque_on_bit=run.torque_on_bit)
    res = compute_analysis(rec, AnalysisOptions(simulate=False, folds=0), log=lambda *a: None)
    (w,) = [w for w in res.summary["warnings"] if w["code"] == "no_stick"]
    assert "not stick-slip" in w["message"] and res.summary["severity"]["stick_fraction"] == 0.0
