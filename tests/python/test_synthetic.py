"""Synthetic records of the rig model: reproducible from the seed, each effect leaves its physical
mark (the sensors' delay, the motor's droop, the noise level, the unmeasured viscous torque), and
bad requests are refused."""
from __future__ import annotations

import math

import numpy as np
import pytest

from drillpy.synthetic import DEFAULTS, EFFECTS, NOISE, declared_config, synthetic_record


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
    from drillpy.simulation import law_torque
    rec = synthetic_record({"viscous_damping": {"bit_viscous_nms": 0.03}}, duration_s=4.0, seed=1, noise=0.0)
    cfg = declared_config()
    slip = rec.bit_speed > 1.0
    law = law_torque(cfg["law"], rec.bit_speed[slip], 0.0, cfg["operation"]["wob_n"])
    assert np.max(np.abs(rec.torque_on_bit[slip] - law)) < 1e-6


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
