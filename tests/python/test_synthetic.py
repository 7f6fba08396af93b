"""Synthetic records of the rig model: reproducible from the seed, each effect leaves its physical
mark (the sensors' delay, the motor's droop, the noise level, the unmeasured viscous torque), and
bad requests are refused."""
from __future__ import annotations

import math

import numpy as np
import pytest

from drillpy.loop.synthetic import DEFAULTS, EFFECTS, NOISE, declared_config, synthetic_record, truth_config


def test_same_seed_same_record_other_seed_other_noise():
    a = synthetic_record(["wob_coupling"], duration_s=2.0, seed=7)
    b = synthetic_record(["wob_coupling"], duration_s=2.0, seed=7)
    c = synthetic_record(["wob_coupling"], duration_s=2.0, seed=8)
    for ch in ("bit_speed", "top_speed", "torque_on_bit", "wob"):
        assert np.array_equal(getattr(a, ch), getattr(b, ch))
    assert not np.allclose(a.wob, c.wob)
    assert a.provenance["synthetic"]["effects"] == {"wob_coupling": DEFAULTS["wob_coupling"]}


def test_measurement_noise_has_the_stated_standard_deviations():
    clean = synthetic_record((), duration_s=6.0, seed=3, noise=0.0)
    noisy = synthetic_record((), duration_s=6.0, seed=3, noise=2.0)
    for ch, sd in NOISE.items():
        d = getattr(noisy, ch) - getattr(clean, ch)
        assert np.std(d) == pytest.approx(2.0 * sd, rel=0.05), ch
        assert abs(np.mean(d)) < 0.1 * sd


def test_sensor_lag_delays_the_channels_by_the_filters_group_delay():
    """A second-order Butterworth at 8 Hz delays a 3 Hz stick-slip by about sqrt(2)/(2 pi 8 Hz) = 28 ms."""
    a = synthetic_record((), duration_s=6.0, seed=1, noise=0.0, fs_hz=1000.0)
    b = synthetic_record({"sensor_lag": {"lowpass_hz": 8.0}}, duration_s=6.0, seed=1, noise=0.0, fs_hz=1000.0)
    x, y = a.bit_speed - a.bit_speed.mean(), b.bit_speed - b.bit_speed.mean()
    lags = np.arange(0, 60)
    c = [np.dot(x[: x.size - k], y[k:]) for k in lags]
    assert lags[int(np.argmax(c))] * 1e-3 == pytest.approx(math.sqrt(2) / (2 * math.pi * 8.0), abs=0.006)


def test_motor_droops_with_the_torque_and_the_ideal_drive_does_not():
    ideal = synthetic_record((), duration_s=6.0, seed=1, noise=0.0)
    motor = synthetic_record({"top_drive_dynamics": {"slope_nms_rad": 0.25, "inertia_kg_m2": 0.02}}, duration_s=6.0,
                             seed=1, noise=0.0)
    assert np.ptp(ideal.top_speed) < 1e-9
    assert np.ptp(motor.top_speed) > 3.0  # rad/s: the motor gives way with the cycle
    # commanded so that the mean speed stays near the preset's 80.9 RPM
    assert np.mean(motor.top_speed) == pytest.approx(80.9 * math.pi / 30, rel=0.15)


def test_viscous_torque_is_not_in_the_torque_channel():
    """The record's torque is the contact torque: with c_v the bit runs slower, yet the recorded
    torque stays on the law (the viscous drag acts outside the load cell)."""
    from drillpy.model.simulation import law_torque
    rec = synthetic_record({"viscous_damping": {"bit_viscous_nms": 0.03}}, duration_s=4.0, seed=1, noise=0.0,
                           nuisance=False)
    cfg = declared_config()
    slip = rec.bit_speed > 1.0
    law = law_torque(cfg["law"], rec.bit_speed[slip], 0.0, cfg["operation"]["wob_n"])
    assert np.max(np.abs(rec.torque_on_bit[slip] - law)) < 1e-6


def test_the_truth_is_drawn_away_from_the_declared_model():
    """Damping, stiffness, law, modes and time step of the truth differ from the declared model's,
    differently for each seed, identically for the same seed."""
    d = declared_config()
    a, da = truth_config(1)
    b, db = truth_config(2)
    assert truth_config(1)[1] == da and da != db
    for t, dr in ((a, da), (b, db)):
        assert t["rom"]["modes"] == 3 and t["string"]["sections"][0]["elements"] == 40
        assert t["simulation"]["dt_s"] == pytest.approx(d["simulation"]["dt_s"] / 4)
        assert 0.03 <= dr["damping_ratio"] <= 0.08 and 0.985 <= dr["gj_factor"] <= 1.015
        assert t["law"]["a4"] != d["law"]["a4"]
    rec = synthetic_record((), duration_s=2.0, seed=1)
    assert rec.provenance["synthetic"]["truth"] == da


def test_effects_outside_the_catalogue_and_new_catalogue_effects_leave_their_mark():
    """A top-speed ramp ramps the top speed; a softer string lowers the stick-slip frequency; string
    friction makes the bit stick longer without showing in the torque channel."""
    base = synthetic_record((), duration_s=8.0, seed=3, noise=0.0)
    ramp = synthetic_record({"top_speed_ramp": {"ramp_fraction": 0.2}}, duration_s=8.0, seed=3, noise=0.0)
    slope = np.polyfit(ramp.time_s, ramp.top_speed, 1)[0]
    assert slope * (6.0 + 8.0) == pytest.approx(0.2 * np.mean(base.top_speed), rel=0.05)  # over settle + record
    soft = synthetic_record({"string_stiffness": {"gj_factor": 0.7}}, duration_s=8.0, seed=3, noise=0.0)

    def freq(r):
        x = r.bit_speed - r.bit_speed.mean()
        f = np.fft.rfftfreq(x.size, r.dt)
        return f[np.argmax(np.abs(np.fft.rfft(x)))]
    assert freq(soft) < freq(base)


def test_bad_requests_name_what_is_wrong():
    with pytest.raises(ValueError, match="effect = 'gremlins': unknown"):
        synthetic_record(["gremlins"])
    with pytest.raises(ValueError, match=r"effects\['sensor_lag'\]\['lowpass_hz'\] = -1"):
        synthetic_record({"sensor_lag": {"lowpass_hz": -1}})
    with pytest.raises(ValueError, match="unknown parameter"):
        synthetic_record({"viscous_damping": {"c": 1.0}})
    with pytest.raises(ValueError, match="fs_hz = 3000"):
        synthetic_record((), fs_hz=3000.0)
    with pytest.raises(ValueError, match="noise = -1"):
        synthetic_record((), noise=-1)
    assert set(EFFECTS) == set(DEFAULTS)
