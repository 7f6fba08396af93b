"""Simulation through the bindings: NumPy oracle, metrics, sweeps, GIL release and Ctrl-C."""
import os
import signal
import threading
import time

import numpy as np
import pytest

import drillpy
from numpy_rom import run_modified_euler

FIELD = drillpy.load_config(preset="thesis-field")


def test_engine_matches_numpy_reference_loop():
    cfg = drillpy.with_overrides(FIELD, duration=3.0, transient=1.0)
    ref = run_modified_euler(cfg, 16.0)
    r = drillpy.simulate(cfg, 16.0)
    stride = cfg["simulation"]["output_stride"]
    np.testing.assert_allclose(r.bit_speed, ref[::stride], rtol=0, atol=1e-7)  # root-solver round-off
    assert r.t[1] - r.t[0] == pytest.approx(stride * 5.12e-4)


def test_run_outputs_and_severity_definition():
    r = drillpy.simulate(FIELD, 10.0)
    n = round(200 / 5.12e-4) // 20 + 1
    for a in (r.t, r.bit_speed, r.bit_angle, r.torque_on_bit, r.top_torque, r.top_speed):
        assert a.shape == (n,) and np.all(np.isfinite(a))
    w = r.t >= 100.0
    ss = (r.bit_speed[w].max() - r.bit_speed[w].min()) / (2 * 10.0)  # Eq. (3.4) on the samples
    assert r.severity >= ss - 1e-12 and r.severity == pytest.approx(ss, rel=0.02)
    assert r.severity > 1.0 and 0.1 < r.stick_fraction < 0.6
    # bit angle is the integral of bit speed
    dth = np.diff(r.bit_angle)
    np.testing.assert_allclose(dth, np.diff(r.t) * 0.5 * (r.bit_speed[1:] + r.bit_speed[:-1]),
                               rtol=0, atol=0.15)


def test_constant_series_input_equals_constant_top_speed():
    cfg = drillpy.with_overrides(FIELD, duration=20.0, transient=5.0)
    a = drillpy.simulate(cfg, 12.0)
    b = drillpy.simulate(cfg, top_speed_series=np.full(100, 12.0), series_dt=1.0)
    np.testing.assert_array_equal(a.bit_speed, b.bit_speed)


def test_sweep_threshold_and_figure_4_8_shape():
    speeds = np.arange(6.0, 28.0)
    ss = drillpy.sweep_severity(FIELD, speeds, progress=False)
    assert ss.shape == (22,)
    thr = drillpy.severity_threshold(speeds, ss)
    assert 15.0 < thr < 21.0  # thesis: 16 rad/s (docs/validation.md)
    assert ss[0] > 1.0 and ss[-1] < 0.1


def test_batched_sweep_agrees_with_the_scalar_reference():
    # runs in SIMD lockstep (issue 16) against the scalar integrator: rounding-level differences
    # (vectorized exp/log, summation order), SS within 1e-4 (tests/cpp/test_batched_integrator.cpp)
    cfg = drillpy.with_overrides(FIELD, modes=10, duration=30.0, transient=10.0)
    speeds = [6.0, 12.0, 18.0, 24.0, 27.0]
    batched = drillpy.sweep_severity(cfg, speeds, progress=False, batched=True)
    scalar = drillpy.sweep_severity(cfg, speeds, progress=False, batched=False)
    np.testing.assert_allclose(batched, scalar, rtol=1e-4)
    assert drillpy._core.Simulation.batch_width() in (2, 4, 8)


def test_progress_callback_and_grid_shape():
    calls = []
    sim = drillpy._core.Simulation(drillpy.model.config.engine_config(FIELD))
    out = sim.sweep([10.0, 20.0, 30.0], [100e3, 200e3], lambda d, t: calls.append((d, t)), 1)
    assert out.shape == (2, 3)
    assert calls[-1] == (6, 6) and all(a[0] < b[0] for a, b in zip(calls, calls[1:]))


def test_sweep_releases_the_gil():
    cfg = drillpy.with_overrides(FIELD, duration=400.0, transient=100.0)
    ticks = []
    done = threading.Event()

    def work():
        drillpy.sweep_severity(cfg, np.arange(6.0, 16.0), progress=False, threads=1)
        done.set()

    th = threading.Thread(target=work)
    th.start()
    while not done.is_set():
        ticks.append(time.perf_counter())
        time.sleep(0.01)
    th.join()
    assert len(ticks) > 10  # the main thread kept running Python while the engine worked


@pytest.mark.skipif(os.name != "posix", reason="needs SIGINT")
def test_ctrl_c_stops_a_sweep():
    cfg = drillpy.with_overrides(FIELD, duration=400.0, transient=100.0)
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    # a shell's background job inherits SIGINT ignored: test with Python's own handler
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        t0 = time.perf_counter()
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            drillpy.sweep_severity(cfg, np.linspace(6, 27, 200), progress=False, threads=1)
        assert time.perf_counter() - t0 < 10.0  # 200 runs would take far longer
    finally:
        signal.signal(signal.SIGINT, old)


def test_law_torque_matches_thesis_values():
    rpm = np.pi / 30
    T = drillpy.law_torque(FIELD["law"], [10 * rpm, 200 * rpm])
    np.testing.assert_allclose(T, [12.8e3, 7.8e3], atol=100)
    T = drillpy.law_torque(drillpy.model.config.thesis_law("tucker_wang"), 1.0)
    assert T[0] == pytest.approx(10.3e3, abs=60)


def test_bad_inputs_raise_value_errors():
    with pytest.raises(ValueError, match="speeds"):
        drillpy.sweep_severity(FIELD, [], progress=False)
    with pytest.raises(ValueError, match=r"sweep.top_speeds_rad_s\[1\] = -3"):
        drillpy.sweep_severity(FIELD, [5.0, -3.0], progress=False)
    with pytest.raises(ValueError, match="top_speed_series"):
        drillpy.simulate(FIELD, top_speed_series=np.array([1.0, np.nan]))


def test_bistable_band_rest_versus_steady_start():
    # At 16 rad/s the field string sticks and slips when started from rest (Eq. 2.10) but keeps
    # drilling smoothly from disturbed steady drilling: the stick-slip cycle and the steady state
    # coexist (docs/validation.md).
    rest = drillpy.simulate(FIELD, 16.0, record=False)
    steady = drillpy.simulate(FIELD, 16.0, record=False, start="steady")
    assert rest.severity > 1.0 and steady.severity < 0.05
    ss = drillpy.sweep_severity(FIELD, [16.0], progress=False, start="steady")
    assert ss[0] == pytest.approx(steady.severity, abs=1e-12)
    with pytest.raises(ValueError, match="start = 'cold'"):
        drillpy.simulate(FIELD, 16.0, start="cold")


def test_threshold_located_by_bisection_to_the_stated_precision():
    from drillpy.model.simulation import refine_threshold, sweep_severity
    cfg = drillpy.with_overrides(drillpy.load_config(preset="thesis-field"), modes=5, duration=120.0, transient=60.0)
    speeds = np.arange(18.0, 30.0, 2.0)
    ss = sweep_severity(cfg, speeds, progress=False)
    r = refine_threshold(cfg, speeds, ss, tol=0.05)
    k = max(i for i in range(speeds.size - 1) if ss[i] > 0.5 >= ss[i + 1])
    assert speeds[k] <= r.below < r.above <= speeds[k + 1]   # inside the grid's last crossing
    assert r.precision <= 0.05 and r.threshold == pytest.approx(0.5 * (r.below + r.above))
    runs = dict(r.evaluations)
    if r.below in runs:
        assert runs[r.below] > 0.5
    if r.above in runs:
        assert runs[r.above] <= 0.5
    again = sweep_severity(cfg, [r.below, r.above], progress=False)  # the bracket straddles SS = 0.5
    assert again[0] > 0.5 >= again[1]
    finer = refine_threshold(cfg, [r.below, r.above], again, tol=0.01)
    assert r.below <= finer.below < finer.above <= r.above and finer.precision <= 0.01
    assert refine_threshold(cfg, speeds, np.zeros(speeds.size)) is None  # no crossing
    with pytest.raises(ValueError, match="tol"):
        refine_threshold(cfg, speeds, ss, tol=0.0)


def test_chapter4_preset_reproduces_the_thesis_threshold_of_16_rad_s():
    """Fig. 4.8: SS > 0.5 below 16 rad/s (deterministic hysteretic model). With the Table 3.1 string
    at WOB = 200 kN and all 100 modes (`thesis-ch4`) the crossing lies between 15.5 and 16.5 rad/s
    (15.98 +- 0.02 by `drillpy sweep --preset thesis-ch4 --refine 0.02`)."""
    from drillpy.model.simulation import sweep_severity
    cfg = drillpy.load_config(preset="thesis-ch4")
    assert cfg["operation"]["wob_n"] == 200e3 and cfg["rom"]["modes"] == 100
    ss = sweep_severity(cfg, [15.5, 16.5], progress=False)
    assert ss[0] > 0.5 > ss[1]


def test_string_friction_loads_the_string_but_not_the_torque_on_bit():
    # operation.string_friction_nm (an extension, not in the thesis): a Coulomb torque T_sf sign(v)
    # on the bit outside its torque sensor. In steady slip the string carries the torque on bit plus
    # T_sf; the torque on bit itself is the one without string friction.
    tsf = 0.3
    cfg = drillpy.load_config(preset="thesis-rig")
    cfg["simulation"].update(duration_s=12.0, transient_s=8.0)
    base = drillpy.load_config(config=cfg)
    cfg["operation"]["string_friction_nm"] = tsf
    cfg = drillpy.load_config(config=cfg)
    assert base["operation"]["string_friction_nm"] == 0.0
    om = 30.0  # above the rig's stick-slip band (SS 0.77 at 20 rad/s): steady slip
    r = drillpy.simulate(cfg, om, start="steady")
    r0 = drillpy.simulate(base, om, start="steady")
    w = r.t >= 8.0
    assert r.severity < 1e-3 and r0.severity < 1e-3
    assert np.all(r.bit_speed[w] > 0.9 * om)
    # the one-mode string's top torque per N m at the bit is 1 + 1.4e-5 (modal truncation)
    string, bit = np.mean(r.top_torque[w]), np.mean(r.torque_on_bit[w])
    assert string - bit == pytest.approx(tsf, rel=1e-3)
    assert bit == pytest.approx(np.mean(r0.torque_on_bit[w]), rel=1e-6)
    assert string == pytest.approx(np.mean(r0.top_torque[w]) + tsf, rel=1e-4)
    # the keyword overrides the configuration like bit_viscous
    a = drillpy.simulate(cfg, om, start="rest")
    b = drillpy.simulate(base, om, start="rest", string_friction=tsf)
    np.testing.assert_array_equal(a.bit_speed, b.bit_speed)
    np.testing.assert_array_equal(a.torque_on_bit, b.torque_on_bit)


def test_start_modes_and_the_lagged_acceleration_are_explicit_options():
    """Eq. (2.3) (rigid) and Eq. (2.10) (rest) are different initial states; the lagged bit
    acceleration of Eq. (3.3) is a different scheme, refused with BDF2, named in the saved config."""
    cfg = drillpy.with_overrides(drillpy.load_config(preset="thesis-field"), modes=10, duration=40, transient=20)
    rest = drillpy.simulate(cfg, 18.0, record=True)
    rigid = drillpy.simulate(cfg, 18.0, start="rigid", record=True)
    assert abs(rest.bit_speed[0]) < 0.05 * 18.0  # Eq. (2.10) on 10 modes: the bit nearly at rest
    assert rigid.bit_speed[0] == pytest.approx(18.0, abs=1e-12)
    ss = drillpy.sweep_severity(cfg, [18.0], progress=False, start="rigid")
    assert ss[0] == pytest.approx(rigid.severity, rel=1e-12)  # the sweep starts the same way
    with pytest.raises(ValueError, match="start"):
        drillpy.sweep_severity(cfg, [18.0], progress=False, start="spinning")
    lag = drillpy.with_overrides(cfg, acceleration="lagged")
    assert drillpy.simulate(lag, 18.0, record=False).config["simulation"]["acceleration"] == "lagged"
    with pytest.raises(ValueError, match="simulation.acceleration"):
        drillpy.simulate(drillpy.with_overrides(lag, scheme="bdf2"), 18.0, record=False)


@pytest.mark.parametrize("kwargs, message", [
    ({"top_speed": "16"}, "top_speed = '16': must be a finite number [rad/s]"),
    ({"wob": [1.0]}, "wob = [1.0]: must be a finite number [N]"),
    ({"top_speed": True}, "top_speed = True"),
])
def test_operating_point_of_the_wrong_type_is_one_clear_error(kwargs, message):
    """Was a raw pybind11 cast error ("Unable to cast Python instance of type str"; issue 13)."""
    cfg = drillpy.load_config(preset="thesis-rig")
    with pytest.raises(ValueError) as e:
        drillpy.simulate(cfg, **kwargs)
    assert str(e.value).startswith(message)
    with pytest.raises(ValueError, match=r"^speeds = \['a'\]: must be a non-empty 1-D list of numbers"):
        drillpy.sweep_severity(cfg, ["a"])


@pytest.mark.parametrize("speed", ["0", "-8"])
def test_a_top_speed_not_forward_is_refused_on_the_command_line(speed, capsys):
    """--top-speed 0 printed "severity": NaN and -8 ran with a negative torque on bit (issue 13)."""
    from drillpy.cli import main
    assert main(["simulate", "--preset", "thesis-rig", "--top-speed", speed, "--json"]) == 2
    err = capsys.readouterr().err
    assert err == f"drillpy: error: operation.top_speed_rad_s = {speed}: must be positive\n"


def _rig_scan(ratios, duration=5.0):
    cfgs = []
    for z in ratios:
        c = drillpy.load_config(preset="thesis-rig")  # one mode, Eq. (5.3): its tanh goes through exp
        c["simulation"].update(duration_s=duration, transient_s=1.0)
        c["damping"] = {"type": "modal", "ratios": [z]}
        cfgs.append(c)
    return cfgs


def test_a_damping_scan_in_lockstep_agrees_with_one_run_at_a_time():
    from drillpy.model.simulation import simulate_many
    cfgs = _rig_scan([0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 0.9, 1.0])  # more than one batch on any host
    many, errors = simulate_many(cfgs)
    assert errors == [""] * len(cfgs)
    ss = []
    for c, r in zip(cfgs, many):
        one = drillpy.simulate(c)
        assert r.bit_speed.shape == one.bit_speed.shape
        np.testing.assert_allclose(r.bit_speed, one.bit_speed, rtol=0, atol=1e-8)  # rounding of exp only
        assert r.severity == pytest.approx(one.severity, rel=1e-8)
        assert r.bit_angle.size == 0 and one.bit_angle.size == one.t.size  # not formed in lockstep
        ss.append(r.severity)
    assert max(ss) - min(ss) > 0.5  # each lane has its own damping: light damping stick-slips, heavy does not
    # the run's bits do not depend on the runs beside it
    alone, _ = simulate_many(cfgs[4:5])
    assert np.array_equal(alone[0].bit_speed, many[4].bit_speed)
    scalar, _ = simulate_many(cfgs, batched=False)
    np.testing.assert_array_equal(scalar[3].bit_angle, drillpy.simulate(cfgs[3]).bit_angle)


def test_a_diverging_run_is_reported_and_the_others_complete():
    from drillpy.model.simulation import simulate_many
    cfgs = _rig_scan([0.1, 0.2])
    bad = _rig_scan([0.2])[0]
    bad["law"]["a7"] = -1.0  # the cubic turns negative: the bit runs away
    results, errors = simulate_many([cfgs[0], bad, cfgs[1]])
    assert results[1] is None and errors[1].startswith("simulation diverged at t = ")
    assert errors[0] == errors[2] == ""
    assert results[2].severity == drillpy.simulate(cfgs[1]).severity
    with pytest.raises(ValueError, match="damping.ratios"):
        simulate_many([cfgs[0], _rig_scan([1.5])[0]])
