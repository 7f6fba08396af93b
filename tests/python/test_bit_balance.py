"""The bit's equation at the cycle's frequency (drillpy.records.bit_balance): the method recovers a
known drive from a simulated rig, and on sample 175 it balances only with the channels' timing."""
import numpy as np
import pytest

import drillpy
from drillpy.records import bit_balance, rigsim
from _testrig import sample175_cleaned, sample175_raw

LAW = {"type": "polynomial", "speed_unit": "rpm", "wob_ref_n": 562.9, "a0": 2.0906, "a1": -0.17888, "a2": 1.92968,
       "a3": 0.0, "a4": 1.94462, "a5": -0.0031835, "a6": -3.0877e-05, "a7": 1.0397e-07, "ref_speed": 89.96, "gain": 1.36}


@pytest.fixture(scope="module")
def halves():
    rec, _ = sample175_cleaned()
    return [rec.select(t0, t0 + 20.0) for t0 in (0.0, 20.0)]


@pytest.fixture(scope="module")
def simulated(halves):
    # the whole-rig model drillpy analyze calibrates on 0-20 s (rounded): its drive is known
    m = rigsim.RigModel(LAW, 0.0303, "rig", 0.25, 0.0186, command_rad_s=17.27, jack_gain_n_rad=181.8,
                        jack_relaxation_s=0.0987, platform_damping=0.75, gj_factor=1.0475,
                        bit_inertia_factor=1.07, coupling_stiffness_nm_rad=41.0)
    sim = rigsim.simulate_model(m, halves[0])
    return m, sim


def test_string_of_the_rig_is_table_5_1s_bar_and_disk():
    k, J = bit_balance.string_of(drillpy.load_config(preset="thesis-rig"))
    assert k == pytest.approx(3.078, abs=0.002)  # G J_p / L of the 1.7 m, 2.5 mm bar at E 220 GPa, nu 0.29
    assert J == pytest.approx(0.009334, abs=2e-6)  # the disk plus a third of the bar


def test_the_drive_of_a_simulated_rig_is_recovered_from_its_encoders(simulated):
    m, sim = simulated
    k, J = bit_balance.string_of(m.config(float(np.mean(sim.top_speed))))
    b = bit_balance.cycle_balance(sim, k, J, valid=sim.time_s >= sim.time_s[0] + 2.0)
    assert 2.0 < b.frequency_hz < 4.0 and b.coherence > 0.9
    # c_m; the platform's lag on the torque (about 10 ms) shows as a small reactive string damping that
    # Eq. (3) carries into Z
    assert b.drive_at_motor.real == pytest.approx(0.25, rel=0.08)
    assert b.motor_inertia == pytest.approx(0.0186, rel=0.10)  # J_m
    assert abs(b.string_damping) < 0.02  # a steel bar's (modal: 0.011 N m s/rad)
    assert b.feed == pytest.approx(b.drive_loss + b.string_loss, rel=1e-9)  # Eq. (1)'s energy, term by term


def test_a_channel_shifted_by_a_known_time_is_found_by_the_timing_fit(simulated):
    m, sim = simulated
    k, J = bit_balance.string_of(m.config(float(np.mean(sim.top_speed))))
    shifted = sim.take(np.arange(len(sim)))
    n_top, n_tq = int(round(0.04 / sim.dt)), int(round(0.03 / sim.dt))
    shifted.top_speed[:] = np.roll(sim.top_speed, -n_top)  # the top encoder reads 40 ms early
    shifted.torque_on_bit[:] = np.roll(sim.torque_on_bit, n_tq)  # the load cell 30 ms late
    grid = np.arange(-0.02, 0.0801, 0.01)
    keep = sim.time_s >= sim.time_s[0] + 2.0
    as_run, as_shifted = (bit_balance.timing_fit(r, grid, grid, stiffness=k, inertia=J, valid=keep)[0]
                          for r in (sim, shifted))
    assert as_shifted["top_lead_s"] - as_run["top_lead_s"] == pytest.approx(0.04, abs=1e-9)
    assert as_shifted["torque_lag_s"] - as_run["torque_lag_s"] == pytest.approx(0.03, abs=1e-9)
    assert abs(as_run["top_lead_s"]) <= 0.0101  # the model's own channels: none, to a step of the grid


def test_sample_175_balances_with_the_tables_string_only_with_the_channels_timing(halves):
    k, J = bit_balance.string_of(drillpy.load_config(preset="thesis-rig"))
    for rec in halves:
        ok = rigsim.reliable_top_speed(rec)
        raw = bit_balance.cycle_balance(rec, k, J, valid=ok)
        timed = bit_balance.cycle_balance(rec, k, J, torque_lag_s=0.03, top_lead_s=0.04, valid=ok)
        assert abs(raw.string_damping) > 0.1  # a reactive residual ten times a steel bar's damping
        assert abs(timed.string_damping) < 0.02
        assert 0.25 < timed.drive_at_motor.real < 0.4  # a droop, as the motor's rating (8 N m / 31.4 rad/s) gives
        assert 0.0 < timed.motor_inertia < 0.01  # a small rotor behind it [kg m^2]


def test_bad_string_parameters_name_the_field(halves):
    with pytest.raises(ValueError, match="stiffness = 0"):
        bit_balance.cycle_balance(halves[0], 0.0, 0.01)
    with pytest.raises(ValueError, match="inertia = nan"):
        bit_balance.cycle_balance(halves[0], 3.0, float("nan"))
    with pytest.raises(ValueError, match="stiffness_above = -1"):
        bit_balance.cycle_balance(halves[0], 3.0, 0.01, stiffness_above=-1.0)
    slow = halves[0].take(np.arange(0, len(halves[0]), 1000))  # 1 Hz: no 1-6 Hz cycle to read
    with pytest.raises(ValueError, match="no cycle in the bit speed between 1 and 6 Hz"):
        bit_balance.cycle_balance(slow, 3.0, 0.01)


def test_the_summary_drillpy_analyze_reports_names_the_timing_that_balances_the_record(halves):
    s = bit_balance.summary(halves[0], drillpy.load_config(preset="thesis-rig"),
                            valid=rigsim.reliable_top_speed(halves[0]))
    assert "does not balance" in s["statement"]
    assert np.hypot(*s["as_recorded"]["string_damping"]) > 0.1
    best = s["best"]
    assert np.hypot(*best["string_damping"]) < 0.01
    # one frequency fixes about the sum of the two timings: the top encoder 60-80 ms ahead of the torque
    assert 0.06 <= best["top_lead_s"] + best["torque_lag_s"] <= 0.08
    assert all(0.05 <= lead + lag <= 0.09 for lead, lag in s["balanced"])
    assert best["feed"] == pytest.approx(best["drive_loss"] + best["string_loss"], rel=1e-9)


def test_an_independent_whole_rig_truths_drive_is_recovered_and_its_channels_balance_as_recorded(tmp_path):
    # benchmarks/whole_rig.py shares no code with drillpy: ten lumped segments, a Stribeck law with ageing, a
    # 20 Hz platform on a one-way load cell, quantized encoders, noise, its rotor 0.013 kg m^2 on a droop of
    # 0.22 N m s/rad, and no skew between its channels
    whole_rig = pytest.importorskip("whole_rig")
    from drillpy.records.cleaning import clean
    from drillpy.records.io import read_record
    path = tmp_path / "truth.mat"
    whole_rig.write_mat(whole_rig.simulate(duration=24.0, seed=5), str(path))
    rec, _ = clean(read_record(path).select(4.0, 24.0))
    k, J = bit_balance.string_of(drillpy.load_config(preset="thesis-rig"))
    ok = rigsim.reliable_top_speed(rec)
    b = bit_balance.cycle_balance(rec, k, J, valid=ok)
    assert abs(b.string_damping) < 0.02  # as recorded: a bar's damping (sample 175 needs 0.15 reactive)
    assert b.drive_at_motor.real == pytest.approx(whole_rig.DEFAULTS["c_m"], rel=0.1)
    assert b.motor_inertia == pytest.approx(whole_rig.DEFAULTS["J_m"], rel=0.15)
    lead, lag, _ = bit_balance.timing_scan(rec, k, J, bit_balance.TIMING_GRID_S, bit_balance.TIMING_GRID_S, valid=ok)[0]
    assert abs(lead + lag) <= 0.0101  # the timing that balances it best: none, to a step of the grid
    # the drive's 95 % intervals hold the truth's droop and rotor
    cfg = drillpy.load_config(preset="thesis-rig")
    di = bit_balance.drive_interval(rec, cfg, bit_balance.summary(rec, cfg, valid=ok), valid=ok)
    assert di["motor_slope"][0] <= whole_rig.DEFAULTS["c_m"] <= di["motor_slope"][1]
    assert di["motor_inertia"][0] <= whole_rig.DEFAULTS["J_m"] <= di["motor_inertia"][1]
    assert di["motor_slope"][1] - di["motor_slope"][0] < 0.2 * whole_rig.DEFAULTS["c_m"]  # and say something


def test_the_drive_interval_holds_the_simulated_rigs_drive_and_spans_sample_175s_timings(simulated, halves):
    m, sim = simulated
    cfg = drillpy.load_config(preset="thesis-rig")
    di = bit_balance.drive_interval(sim, cfg, bit_balance.summary(sim, cfg))
    assert di["motor_slope"][0] <= m.motor_slope_nms_rad <= di["motor_slope"][1]
    assert di["motor_inertia"][0] <= m.motor_inertia_kg_m2 <= di["motor_inertia"][1]
    # on the record every timing that balances as well gives another drive: the interval spans them
    ok = rigsim.reliable_top_speed(halves[0])
    s = bit_balance.summary(halves[0], cfg, valid=ok)
    di = bit_balance.drive_interval(halves[0], cfg, s, valid=ok)
    assert len(di["timings"]) >= 2 and len(di["blocks"]) == bit_balance.DRIVE_BLOCKS
    for r in di["timings"] + di["blocks"]:
        assert di["motor_slope"][0] <= r["motor_slope"] <= di["motor_slope"][1]
        assert di["motor_inertia"][0] <= r["motor_inertia"] <= di["motor_inertia"][1]
    assert 0.2 < di["motor_slope"][0] < s["best"]["motor_slope"] < di["motor_slope"][1] < 0.4
    with pytest.raises(ValueError, match="blocks"):
        bit_balance.drive_interval(halves[0], cfg, s, valid=ok, blocks=8)  # 2.5 s blocks: too short


def test_the_loop_brings_the_channels_to_the_bit_encoders_time_before_anything_else(halves):
    from drillpy.loop import LoopOptions
    from drillpy.loop.data import prepare
    raw = sample175_raw().select(0.0, 20.0)
    cfg = drillpy.load_config(preset="thesis-rig")
    data = prepare(raw, cfg, LoopOptions(channel_timing="auto"))
    ct = data.channel_timing
    # 40 and 50 ms of top lead balance it nearly alike on this part (R^2 within a few thousandths)
    assert ct["top_lead_s"] in (0.04, 0.05) and ct["torque_lag_s"] == 0.03 and ct["r2"] > 0.9 > ct["r2_as_recorded"]
    # the aligned record balances the bit's equation as recorded: the shifted channels are what the loop reads
    k, J = bit_balance.string_of(cfg)
    b = bit_balance.cycle_balance(data.record, k, J, valid=rigsim.reliable_top_speed(data.record))
    assert abs(b.string_damping) < 0.03  # a bar's damping, where as recorded it is 0.15
    assert prepare(raw, cfg, LoopOptions(channel_timing="none")).channel_timing is None  # as recorded
    shifted = bit_balance.aligned(raw, 0.04, 0.03)
    n = int(round(0.04 / raw.dt))
    assert np.isnan(shifted.top_speed[:n]).all() and np.array_equal(shifted.top_speed[n:], raw.top_speed[:-n])
    for bad, msg in (("later", "channel_timing = 'later'"), ((0.04, 0.5), r"channel_timing\[1\] \(torque lag\)")):
        with pytest.raises(ValueError, match=msg):
            LoopOptions(channel_timing=bad).validate()
    with pytest.raises(ValueError, match="top_lead_s = inf"):
        bit_balance.aligned(raw, float("inf"), 0.0)


def test_a_timing_is_the_acquisitions_only_where_the_bit_equation_holds_at_it_and_fails_as_recorded():
    # sample 175: with the string's k and J fitted at every timing the equation holds as recorded at R^2 0.71
    # and at 0.94 with the top 40-50 ms early and the torque 30 ms late, a skew, whatever string is declared.
    # The validation suite's truths have none: a motor (three modes read as one spring) and a motor beside
    # a string's GJ x 0.85 gain a few hundredths from their best shifts, which a string with more modes, or
    # softer than declared, makes up
    import sys
    from pathlib import Path
    from drillpy.loop.synthetic import declared_config, synthetic_record
    from drillpy.records.cleaning import clean
    rec, _ = clean(sample175_raw().select(0.0, 20.0))
    part = rec.select(0.0, 10.0)
    cfg = drillpy.load_config(preset="thesis-rig")
    t = bit_balance.identify_timing(part, cfg, valid=rigsim.reliable_top_speed(part))
    assert t["skew"] and t["top_lead_s"] in (0.04, 0.05) and t["torque_lag_s"] == 0.03
    assert t["r2"] > 0.9 and t["r2"] - t["r2_as_recorded"] > 0.2 and t["stiffness_nm_rad"] < t["declared_stiffness_nm_rad"]
    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
    import loop_validation as LV
    for seed in (13, 34):  # the motor truth; the motor with a softer string
        case = next(c for c in LV.CASES if c.seed == seed and "top_drive_dynamics" in c.effects)
        truth, _ = clean(synthetic_record(case.effects, duration_s=LV.DURATION_S, seed=case.seed, fs_hz=LV.RATE_HZ,
                                          noise=case.noise))
        t = bit_balance.identify_timing(truth, declared_config(), valid=rigsim.reliable_top_speed(truth))
        assert t["r2"] > bit_balance.TIMING_MIN_R2 and 0 < t["r2"] - t["r2_as_recorded"] < bit_balance.TIMING_MIN_GAIN
        assert not t["skew"] and "one-spring" in t["reason"]
    # a record too short for the balance is read as recorded, not refused
    t = bit_balance.identify_timing(rec.select(0.0, 2.0), cfg)
    assert not t["skew"] and (t["top_lead_s"], t["torque_lag_s"]) == (0.0, 0.0) and "needs 4 s" in t["reason"]


def test_auto_timing_is_identified_on_the_calibration_part_only():
    # the validation half read with its torque 100 ms later still (another acquisition setting): the whole
    # record's best timing moves with it, the loop's does not (a prediction uses only what is known beforehand)
    import dataclasses
    from drillpy.loop import LoopOptions
    from drillpy.loop.data import prepare
    from drillpy.records.cleaning import clean
    raw = sample175_raw().select(0.0, 20.0)
    cfg = drillpy.load_config(preset="thesis-rig")
    T = raw.torque_on_bit.copy()
    later = np.r_[np.full(100, np.nan), T[:-100]]
    T[raw.time_s >= 10.0] = later[raw.time_s >= 10.0]
    mod = dataclasses.replace(raw, torque_on_bit=T)
    rec, _ = clean(mod)
    whole = bit_balance.identify_timing(rec, cfg, valid=rigsim.reliable_top_speed(rec))
    assert whole["top_lead_s"] > 0.05
    ct = prepare(mod, cfg, LoopOptions(channel_timing="auto")).channel_timing
    assert ct["top_lead_s"] in (0.04, 0.05) and ct["torque_lag_s"] == 0.03  # the unmodified part's (near-tied)


def test_predict_reads_a_record_at_the_timing_its_loop_model_was_calibrated_at():
    # a loop model that carries the channels' timing (model.json -> channel_timing) is scored on the record
    # brought to that timing, as the loop scored it: the same E as the record aligned by hand, not the E as recorded
    from drillpy.loop import LoopModel
    from drillpy.loop.prediction import predict_record
    raw = sample175_raw().select(20.0, 30.0)
    cfg = drillpy.load_config(preset="thesis-rig")

    def model(ct):
        return LoopModel(cfg, dict(cfg["law"]), 8.5, 557.1, {}, damping_held=True, metric_scale=(4.0, 0.64),
                         channel_timing=ct)
    timed = LoopModel.from_dict(model({"top_lead_s": 0.04, "torque_lag_s": 0.03, "from": "given"}).to_dict())
    assert timed.channel_timing == {"top_lead_s": 0.04, "torque_lag_s": 0.03, "from": "given"}
    E_timed = predict_record(timed, raw, realizations=0).short_horizon_error
    E_aligned = predict_record(model(None), bit_balance.aligned(raw, 0.04, 0.03), realizations=0).short_horizon_error
    E_recorded = predict_record(model(None), raw, realizations=0).short_horizon_error
    assert E_timed == pytest.approx(E_aligned, rel=2e-3)  # the operating point's mean differs by the shifted ends
    assert E_timed < E_recorded - 0.01  # the bit's equation balances at that timing: the horizons fit better
    with pytest.raises(ValueError, match="channel_timing"):
        LoopModel.from_dict({**timed.to_dict(), "channel_timing": {"top_lead_s": "late"}})


def test_a_rig_models_short_horizon_error_reads_the_record_at_the_timing_its_file_keeps(simulated, halves):
    # drillpy analyze --channel-timing: the whole-rig model keeps the timing (model.json -> channel_timing) and
    # its E reads a record at it, as the loop's does; an impossible shift in a model file is one error naming it
    import dataclasses
    from drillpy.loop.prediction import short_horizon_error
    m, _ = simulated
    piece = halves[1].select(20.0, 30.0)
    timed = rigsim.RigModel.from_dict(dataclasses.replace(
        m, channel_timing={"top_lead_s": 0.04, "torque_lag_s": 0.03, "from": "given"}).to_dict())
    assert timed.channel_timing["torque_lag_s"] == 0.03
    E_timed = short_horizon_error(timed, piece, m.command_rad_s, threads=1)
    E_aligned = short_horizon_error(m, bit_balance.aligned(piece, 0.04, 0.03), m.command_rad_s, threads=1)
    E_recorded = short_horizon_error(m, piece, m.command_rad_s, threads=1)
    assert E_timed == pytest.approx(E_aligned, rel=2e-3) and E_timed < E_recorded - 0.01
    with pytest.raises(ValueError, match="channel_timing"):
        rigsim.RigModel.from_dict({**timed.to_dict(), "channel_timing": {"top_lead_s": 0.5, "torque_lag_s": 0.0}})


def test_aligned_moves_each_readings_flags_with_it():
    from drillpy.records.io import Flag
    raw = sample175_raw().select(0.0, 2.0)
    raw.flags["torque_on_bit"][100] |= int(Flag.SPIKE | Flag.REPAIRED)
    out = bit_balance.aligned(raw, 0.0, 0.03)  # the torque read 30 samples (1 kHz) earlier
    assert out.flags["torque_on_bit"][70] == int(Flag.SPIKE | Flag.REPAIRED) and out.flags["torque_on_bit"][100] == 0
    assert out.torque_on_bit[70] == raw.torque_on_bit[100] and np.isnan(out.torque_on_bit[-30:]).all()
    assert (out.flags["torque_on_bit"][-30:] & int(Flag.NONFINITE)).all()


def test_a_record_with_a_steady_top_speed_and_no_skew_is_left_as_recorded():
    # the loop's synthetic truths turn the top at a constant speed: its lead changes nothing and stays 0, and
    # their torque is not late
    from drillpy.loop.synthetic import declared_config, synthetic_record
    from drillpy.records.cleaning import clean
    rec, _ = clean(synthetic_record({"static_friction": {}}, duration_s=20.0, seed=18, fs_hz=500.0))
    t = bit_balance.identify_timing(rec, declared_config(), valid=rigsim.reliable_top_speed(rec))
    assert (t["top_lead_s"], t["torque_lag_s"]) == (0.0, 0.0)
