"""Robust tuning of top-drive controllers and the drives side by side (issue 15, items 2-4):
drillpy.control and ``drillpy control``."""
import json

import numpy as np
import pytest
from conftest import run_cli

from drillpy.control.comparison import compare_drives, drive_threshold, p_window
from drillpy.uncertainty.binomial import wilson_interval
from drillpy.control.episode import motor_torque, run_episode
from drillpy.control.tuning import (FACTOR_RANGE, STALL_FRACTION, Window, bootstrap_p, controlled_drive, drive_gains,
                                    score, tune, window_severity)
from drillpy.model.config import load_config, with_overrides
from drillpy.uncertainty.process import THESIS_PSD, scaled_to_std

FIELD = load_config(preset="thesis-field")
J = 2000.0  # an assumed field top drive [kg m^2] (docs/control.md)
SHORT = dict(warmup=50.0, duration=30.0, transient=10.0)


def test_score_counts_stalled_runs_and_the_tie_break_never_outweighs_one_run():
    ss = np.full((2, 5, 4), 0.2)
    ss[0, 0, 0] = np.inf  # a stalled run: a failure, left out of the mean SS
    s, p, m = score(ss)
    assert p == pytest.approx(1 / 40)
    assert m == pytest.approx(0.2)
    worse = ss.copy()
    worse[1, 1, 1] = 0.6  # one more run above SS = 0.5
    assert score(worse)[0] > score(ss)[0]
    big_ss = np.where(np.isfinite(ss), 0.49, ss)
    assert score(big_ss)[0] < score(worse)[0]  # mean SS 0.49 against 0.2 does not beat one more failure


def test_drive_gains_are_the_engines_tuning():
    g = drive_gains(with_overrides(FIELD, top_drive=controlled_drive("soft_speed", J)))
    # SoftSpeed: kp = Z = J_p sqrt(G rho) of the top section, ki = J w_1^2 (docs/control.md: 464.9, 1369)
    assert g["kp_nms_rad"] == pytest.approx(464.9, rel=1e-3)
    assert g["ki_nm_rad"] == pytest.approx(J * g["omega1_rad_s"] ** 2, rel=1e-12)
    with pytest.raises(ValueError, match="top_drive.type"):
        drive_gains(FIELD)


def test_common_random_numbers_and_sample_independence():
    w3 = Window([10.0, 16.0], [245e3], 3, 7, **SHORT)
    w2 = Window([10.0, 16.0], [245e3], 2, 7, **SHORT)
    a = window_severity(FIELD, None, w3)
    b = window_severity(FIELD, None, w2)
    assert np.array_equal(a[:, :2], b)  # sample i depends only on (seed, i)
    c = window_severity(FIELD, None, w2, seed=8)
    assert not np.array_equal(b, c)  # another seed: new samples
    assert np.array_equal(window_severity(FIELD, None, w2, threads=1), window_severity(FIELD, None, w2, threads=2))
    strong = Window([10.0, 16.0], [245e3], 2, 7, psd=scaled_to_std(THESIS_PSD, 0.2), **SHORT)
    assert strong.as_dict()["psd"]["A0"] > w2.as_dict()["psd"]["A0"]
    assert np.std(window_severity(FIELD, None, strong)) != np.std(b)  # the eta amplitude reaches the runs


def test_a_drive_that_gives_way_stalls_and_counts_as_a_failure():
    # ZTorque with a 60-s torque filter at 6 rad/s: the set point falls with the rising string torque
    # and the bit stays stuck (its SS is small: it does not vary). The run must count as a failure.
    drive = controlled_drive("z_torque", J, None, {"torque_filter_s": 60.0})
    w = Window([6.0], [245e3], 1, 1, **SHORT)
    det = window_severity(FIELD, drive, w, deterministic=True)
    e = run_episode(with_overrides(FIELD, duration=80.0, transient=50.0), "z", drive, 6.0)
    assert e.stick_fraction > 0.9 and e.severity < 0.5  # stuck, yet SS alone reads "no stick-slip"
    assert np.mean(e.bit_speed[e.t >= 50.0]) < STALL_FRACTION * 6.0
    assert np.isinf(det[0, 0, 0])
    assert score(det)[1] == 1.0


def test_stalled_runs_enter_the_comparison_as_stick_slip():
    drives = {"stiff": controlled_drive("stiff", J), "giving_way": controlled_drive("z_torque", J, None,
                                                                                    {"torque_filter_s": 60.0})}
    w = Window([6.0, 20.0], [245e3], 2, 3, **SHORT)
    comp = compare_drives(FIELD, drives, w, reference="stiff", validation_seed=3, bootstrap=20)
    g = comp["giving_way"]
    assert np.isinf(g["map"][0, 0]) and np.all(np.isinf(g["severity"][0, :, 0]))
    assert g["p_by_speed"][0] == 1.0 and g["stalled_fraction"] >= 0.5
    assert g["deterministic_threshold"]["threshold_method"] == "bisection"  # SS's threshold, as drillpy sweep's


def test_the_deterministic_threshold_is_the_sweeps_bisection_with_its_precision_and_rpm():
    """Issue 31: one threshold per string, drive and WOB: control's is drillpy sweep's bisection, printed
    with its +- and its RPM equivalent (no grid interpolation)."""
    from drillpy.reports.control import _threshold_text
    cfg = with_overrides(FIELD, duration=60.0, transient=30.0)
    t = drive_threshold(cfg, None, 245e3, [10.0, 24.0])
    assert t["threshold_method"] == "bisection" and 10.0 < t["threshold_rad_s"] < 24.0
    assert t["threshold_precision_rad_s"] <= 0.02 and t["threshold_rpm"] == pytest.approx(
        t["threshold_rad_s"] * 30 / np.pi)
    lo, hi = t["threshold_bracket_rad_s"]
    assert hi - lo <= 0.04 + 1e-12
    assert _threshold_text({"deterministic_threshold": t}) == (
        f"{t['threshold_rad_s']:.2f} +- {t['threshold_precision_rad_s']:.2f} "
        f"({t['threshold_rpm']:.1f} +- {t['threshold_precision_rpm']:.1f} RPM)")
    assert _threshold_text({"deterministic_threshold": drive_threshold(cfg, None, 245e3, [24.0, 30.0])}) == \
        "none in window"


def test_control_and_sweep_give_one_threshold(tmp_path):
    """The same configuration, drive and WOB: drillpy control's deterministic threshold equals drillpy
    sweep's bisection within the bisection's precision (the ideal drive and the stiff PI)."""
    cfg = tmp_path / "short.json"
    cfg.write_text(json.dumps(with_overrides(FIELD, duration=60.0, transient=30.0)))
    r = run_cli("control", "--config", str(cfg), "--drive-inertia", "2000", "--torque-limit", "50000", "--speeds",
                "10,24", "--wob", "245kN", "--samples", "2", "--validation-samples", "2", "--grid", "2", "--refine",
                "0", "--bootstrap", "20", "--warmup", "10", "--duration", "20", "--transient", "5", "--controllers",
                "z_torque", "--out", str(tmp_path / "ctl"), "--no-progress")
    assert r.returncode == 0, r.stderr
    drives = json.loads((tmp_path / "ctl" / "control.json").read_text())["comparison"]
    sweep = ["sweep", "--config", str(cfg), "--wob", "245kN", "--json", "--no-progress"]
    for label, extra in (("ideal", []), ("stiff", ["--controller", "stiff", "--drive-inertia", "2000",
                                                    "--torque-limit", "50000"])):
        s = run_cli(*sweep, "--speeds", "10,14,18,22,26", *extra)  # another grid: the same threshold
        assert s.returncode == 0, s.stderr
        sw, ctl = json.loads(s.stdout), drives[label]["deterministic_threshold"]
        assert ctl["threshold_rad_s"] is not None and sw["threshold_rad_s"] is not None, label
        assert abs(ctl["threshold_rad_s"] - sw["threshold_rad_s"]) <= (
            ctl["threshold_precision_rad_s"] + sw["threshold_precision_rad_s"]), (label, ctl, sw)
    ideal = drives["ideal"]["deterministic_threshold"]
    assert (f"deterministic at WOB 245 kN: SS > 0.5 below {ideal['threshold_rad_s']:.2f} +- "
            f"{ideal['threshold_precision_rad_s']:.2f} rad/s ({ideal['threshold_rpm']:.1f} +- "
            f"{ideal['threshold_precision_rpm']:.1f} RPM, bisection)") in r.stdout


def test_motor_torque_is_the_interval_mean_of_the_drive_equation():
    # J Omega' = u - T_top with Omega = sin t, T_top = cos t: the mean of u over [a, b] is
    # J (sin b - sin a) / h + (sin b - sin a) / h.
    t = np.linspace(0.0, 10.0, 2001)
    tm, u = motor_torque(t, np.sin(t), np.cos(t), 3.0)
    h = t[1] - t[0]
    exact = 3.0 * np.diff(np.sin(t)) / h + np.diff(np.sin(t)) / h
    # the J term is exact; the string torque's trapezoidal mean errs by at most h^2 max|T''| / 12
    assert np.max(np.abs(u - exact)) <= h * h / 12 * (1 + 1e-6)
    assert np.allclose(tm, t[:-1] + h / 2)
    assert np.array_equal(motor_torque(t, np.sin(t), np.cos(t), None)[1], 0.5 * (np.cos(t[1:]) + np.cos(t[:-1])))


def test_wilson_band_and_bootstrap():
    from scipy.stats import binomtest
    lo, hi = wilson_interval(np.array([0.0, 0.5, 1.0]), 40)
    assert lo[0] == 0.0 and 0.0 < hi[0] < 0.1 and lo[1] < 0.5 < hi[1] and hi[2] == 1.0
    for k, n in ((0, 9), (3, 18), (18, 18)):  # SciPy's Wilson interval, to rounding
        ci = binomtest(k, n).proportion_ci(0.9, method="wilson")
        assert np.allclose(wilson_interval(k / n, n), (ci.low, ci.high), atol=1e-12)
    none = p_window(np.zeros((1, 9, 2)))  # no stick-slip in 9 samples: P <= 0.23, not [0, 0]
    assert none["value"] == 0.0 and none["low"] == 0.0 and none["high"] == pytest.approx(0.2311, abs=1e-4)
    rng = np.random.default_rng(0)
    ss = rng.uniform(0, 1, (1, 200, 3))
    b = bootstrap_p(ss, 200, 1)
    assert b["low"] <= b["value"] <= b["high"]
    assert b["value"] == pytest.approx(np.mean(ss > 0.5))
    d = bootstrap_p(ss, 200, 1, reference=ss)
    assert d["value"] == d["low"] == d["high"] == 0.0  # paired: the same samples cancel


@pytest.fixture(scope="module")
def field_study():
    """Tuned z_torque and soft_speed on a small window, compared on new samples (common to the tests below)."""
    w = Window([8.0, 12.0, 16.0, 20.0, 22.0], [245e3], 4, 1, **SHORT)
    tunings = {c: tune(FIELD, c, w, inertia=J, torque_limit=50e3, grid=2, refine_evaluations=0, bootstrap=20)
               for c in ("soft_speed", "z_torque")}
    drives = {"stiff": controlled_drive("stiff", J, 50e3), "z_torque": controlled_drive("z_torque", J, 50e3),
              "soft_speed_tuned": controlled_drive("soft_speed", J, 50e3, tunings["soft_speed"].gains)}
    val = Window(w.speeds, w.wobs, 6, 2, **SHORT)
    return tunings, compare_drives(FIELD, drives, val, reference="stiff", validation_seed=2, bootstrap=50)


def test_tuning_stays_in_its_bounds_and_reports_the_nominal_tuning(field_study):
    tunings, _ = field_study
    for t in tunings.values():
        assert len(t.evaluations) == 5  # a 2 x 2 grid and the nominal tuning
        for f in t.factors.values():
            assert FACTOR_RANGE[0] * (1 - 1e-9) <= f <= FACTOR_RANGE[1] * (1 + 1e-9)
        assert t.score <= t.nominal_score
        assert t.spread["resamples"] == 20
        # a 2 x 2 grid has its points on the bounds: an optimum off the nominal tuning is flagged
        on_bound = [k for k, f in t.factors.items() if min(abs(f / b - 1) for b in FACTOR_RANGE) < 1e-9]
        assert t.at_bound == on_bound


def test_impedance_matching_lowers_the_stick_slip_speed_of_the_stiff_drive(field_study):
    # issue 15's check: ZTorque lowers the speed below which stick-slip occurs, deterministically
    # (thesis-field's ideal drive: 19.70 rad/s at 245 kN) and as the 5 % speed under uncertainty.
    _, comp = field_study
    stiff, z = comp["stiff"], comp["z_torque"]
    assert stiff["deterministic_threshold_rad_s"] is not None and stiff["deterministic_threshold_rad_s"] > 16.0
    assert z["deterministic_threshold_rad_s"] is None or z["deterministic_threshold_rad_s"] < 12.0
    assert stiff["p05_speed_rad_s"] is not None and stiff["p05_speed_rad_s"] > 16.0
    assert z["p05_speed_rad_s"] is None or z["p05_speed_rad_s"] < 12.0
    assert z["p_vs_reference"]["high"] < 0.0  # paired on the same new samples: a significant reduction


def test_control_command_writes_its_report(tmp_path):
    out = tmp_path / "ctl"
    cmd = ["control", "--preset", "thesis-field", "--drive-inertia", "2000",
           "--torque-limit", "50000", "--speeds", "10,18", "--wobs-kn", "245", "--samples", "2",
           "--validation-samples", "2", "--grid", "2", "--refine", "2", "--bootstrap", "20", "--warmup", "30",
           "--duration", "20", "--transient", "5", "--controllers", "z_torque", "--out", str(out), "--json",
           "--no-progress"]
    r = run_cli(*cmd)
    assert r.returncode == 0, r.stderr
    res = json.loads(r.stdout)
    assert set(res["drives"]) == {"ideal", "stiff", "z_torque", "z_torque_tuned"}
    js = json.loads((out / "control.json").read_text())
    assert js["validation_window"]["seed"] == js["tuning_window"]["seed"] + 1
    assert js["torque_limit_nm"] == 50000
    for name in ("maps.png", "p_vs_speed.png", "episode.png", "tuning_z_torque.png", "report.md"):
        assert (out / name).stat().st_size > 1000
    assert "deterministic threshold, bisection [rad/s]" in (out / "report.md").read_text()
    for d in res["drives"].values():  # the bisection's precision beside every threshold found
        t = d["deterministic_threshold"]
        assert t["threshold_rad_s"] == d["deterministic_threshold_rad_s"] and t["threshold_method"] == "bisection"
        assert t["threshold_rad_s"] is None or t["threshold_precision_rad_s"] <= 0.02
    for e in js["episodes"].values():  # the motor torque demanded, against the limit
        assert e["peak_motor_torque_nm"] > e["mean_motor_torque_nm"] > 0
        assert e["within_limit"] in (True, None)


@pytest.mark.parametrize("args, message", [
    (["--drive-inertia", "-1"], "--drive-inertia = -1"),
    (["--drive-inertia", "2000", "--controllers", "pid"], "controllers: 'pid'"),
    (["--drive-inertia", "2000", "--torque-limit", "0"], "--torque-limit = 0"),
    (["--drive-inertia", "2000", "--speeds", "10,-3"], "speeds"),
    (["--drive-inertia", "2000", "--factor-range", "2,5"], "factor_range = (2, 5)"),
])
def test_control_command_refuses_bad_input(tmp_path, args, message):
    r = run_cli("control", "--preset", "thesis-field", *args, "--out", str(tmp_path / "o"))
    assert r.returncode == 2
    assert message in r.stderr and r.stderr.count("\n") == 1
    assert not (tmp_path / "o").exists()
