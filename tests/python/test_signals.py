"""Signal analysis: smoothing, filter, derivative, cycles, mean cycle, eta_exp, PSD fit, statistics."""
import numpy as np
import pytest

from _testrig import sample175_cleaned, sample175_cycles
from drillpy.records import signals as sig
from drillpy.records.io import RPM


def test_swa_keeps_constants_and_lines_and_skips_nan():
    x = 2.0 + 0.5 * np.arange(50.0)
    y = sig.swa(x, 7)
    np.testing.assert_allclose(y[3:-3], x[3:-3], rtol=1e-14)  # a centred mean of a line is the line
    x[10] = np.nan
    assert np.isfinite(sig.swa(x, 5)[10])
    assert sig.swa(x, 4)[20] == pytest.approx(x[20])  # even windows are made odd (centred)
    with pytest.raises(ValueError, match="window"):
        sig.swa(x, 0)


def test_rig_lowpass_is_the_10hz_second_order_butterworth():
    fs = 1000.0
    t = np.arange(0, 4, 1 / fs)
    assert np.allclose(sig.rig_lowpass(np.full(t.size, 3.0), fs), 3.0)  # starts at rest, DC gain 1
    for f, gain in ((1.0, 1.0), (10.0, 2 ** -0.5), (100.0, 0.01)):
        y = sig.rig_lowpass(np.sin(2 * np.pi * f * t), fs)
        amp = np.max(np.abs(y[t > 2]))
        assert amp == pytest.approx(gain, rel=0.02 if f < 100 else 0.15)
    with pytest.raises(ValueError, match="non-finite"):
        sig.rig_lowpass(np.array([1.0, np.nan, 2.0]), fs)


def test_platform_response_is_the_20hz_second_order_mode():
    # unit gain at rest, 1 / (2 zeta) at its natural frequency (the bilinear map shifts it by 0.13 %),
    # 1 / ((f / f_n)^2 - 1) above it (at 100 Hz the map warps the frequency by 3 %)
    fs = 1000.0
    t = np.arange(0, 6, 1 / fs)
    assert np.allclose(sig.platform_response(np.full(t.size, 2.5), fs, 20.0, 0.3), 2.5)
    for f, gain in ((1.0, 1.0), (20.0, 1.0 / (2 * 0.3)), (100.0, 1.0 / ((100 / 20) ** 2 - 1))):
        y = sig.platform_response(np.sin(2 * np.pi * f * t), fs, 20.0, 0.3)
        assert np.max(np.abs(y[t > 4])) == pytest.approx(gain, rel=0.03 if f < 100 else 0.1), f  # warped at 100 Hz
    for bad, match in (({"damping": 0.0}, "damping"), ({"natural_hz": 600.0}, "natural_hz")):
        with pytest.raises(ValueError, match=match):
            sig.platform_response(np.ones(10), fs, **bad)


def test_derivative_of_a_sine():
    dt = 1e-3
    t = np.arange(0, 2, dt)
    w = 2 * np.pi * 3.0
    d = sig.derivative(np.sin(w * t), dt)
    assert np.max(np.abs(d - w * np.cos(w * t))) < 1e-3 * w
    d0 = sig.derivative(np.sin(w * t), dt, window_s=0)
    assert np.max(np.abs(d0[1:-1] - w * np.cos(w * t[1:-1]))) < 2e-4 * w


def test_severity_is_one_for_full_stick_slip():
    t = np.linspace(0, 10, 5001)
    om = 8.0
    assert sig.severity(om * (1 - np.cos(2 * np.pi * t)), om) == pytest.approx(1.0, rel=1e-6)


def _stick_slip(period=0.4, stick=0.1, amp=20.0, n_cycles=12, dt=1e-3):
    slip = period - stick
    tau = np.arange(0, period * n_cycles, dt) % period
    v = np.where(tau < stick, 0.0, amp * np.sin(np.pi * np.clip(tau - stick, 0, slip) / slip))
    return np.arange(v.size) * dt, v


def test_segmentation_of_a_synthetic_stick_slip():
    t, v = _stick_slip()
    thr = 0.02 * 20.0
    cyc = sig.segment_cycles(v, 1e-3, thr)
    assert cyc.valid.sum() == 10  # the first and last partial cycles are not counted
    np.testing.assert_allclose(cyc.period_s[cyc.valid], 0.4, atol=1.5e-3)
    np.testing.assert_allclose(cyc.stick_s[cyc.valid], 0.1, atol=5e-3)
    lab = cyc.branch_labels(v.size)
    acc = np.gradient(v, 1e-3)
    assert np.mean(acc[lab == 1] >= -1e-9) > 0.99 and np.mean(acc[lab == -1] <= 1e-9) > 0.99
    st = sig.cycle_statistics(cyc, v, np.full(v.size, 10.0))
    np.testing.assert_allclose(st["ss"], 1.0, atol=1e-3)  # (20 - 0) / (2 x 10)
    # excluded samples invalidate the cycles that hold them
    ok = np.ones(v.size, bool)
    ok[2000] = False
    assert sig.segment_cycles(v, 1e-3, thr, valid=ok).valid.sum() == 9


def test_mean_cycle_separates_the_branches_and_eta_is_recovered():
    t, v = _stick_slip(n_cycles=60)
    cyc = sig.segment_cycles(v, 1e-3, 0.4)
    lab = cyc.branch_labels(v.size)
    acc = sig.derivative(v, 1e-3)
    tref = 3.0 - 0.05 * v
    hyst = 0.2 * np.sign(acc)
    mc = sig.mean_cycle(v, tref + hyst, acc, lab, grid=np.linspace(1, 19, 19), half_width=0.5)
    np.testing.assert_allclose(np.nanmedian(mc.upper - mc.lower), 0.4, atol=0.02)
    assert np.all(mc.accel_upper[np.isfinite(mc.accel_upper)] > 0)
    eta = 0.1 * np.sin(2 * np.pi * 0.7 * t)
    mc2 = sig.mean_cycle(v, tref * (1 + eta), acc, lab, grid=np.linspace(0, 20, 41))
    e = sig.eta_exp(t, v, tref * (1 + eta), lab, mc2)
    got = e.eta[e.measured]
    want = eta[np.flatnonzero(e.measured) + np.searchsorted(t, e.t[0])]
    assert np.corrcoef(got, want)[0, 1] > 0.98
    assert np.std(got) == pytest.approx(np.std(want), rel=0.05)
    assert abs(e.statistics()["mean"]) < 0.01


def test_statistics_identities():
    x = np.array([1.0, 2.0, 3.0, 6.0])
    s = sig.sample_statistics(x)
    assert s["cv"] == pytest.approx(np.std(x, ddof=1) / 3.0)
    d = np.array([0.1, -0.2, 0.3, 0.0])
    assert sig.var_mse(x + d, x) == pytest.approx(np.var(d ** 2, ddof=1))
    with pytest.raises(ValueError):
        sig.sample_statistics([1.0])


def test_sample175_cycles_match_the_readme_and_thesis():
    rec, rep = sample175_cleaned()
    cyc, acc, lab = sample175_cycles()
    assert cyc.valid.sum() >= 95
    f = sig.dominant_frequency(rec.bit_speed, rec.sample_rate_hz)
    assert 2.6 <= f <= 2.9  # README: dominant frequency about 2.6-2.9 Hz
    per = np.median(cyc.period_s[cyc.valid])
    assert 1 / 2.9 <= per <= 1 / 2.5
    ss = sig.severity(rec.bit_speed, rec.top_speed)
    assert 1.1 < ss < 1.4  # 0 to 200 RPM around a mean top speed near 80 RPM (Eq. 3.4)
    mc = sig.mean_cycle(rec.bit_speed, rec.torque_on_bit, acc, lab)
    rpm = mc.speed * RPM
    band = (rpm > 25) & (rpm < 150)
    assert np.nanmean(mc.upper[band] - mc.lower[band]) > 0.1  # hysteresis: the branches differ
    i25, i150 = np.argmin(abs(rpm - 25)), np.argmin(abs(rpm - 150))
    assert mc.all[i150] < 0.7 * mc.all[i25]  # velocity weakening (Fig. 5.7b)
    e = sig.eta_exp(rec.time_s, rec.bit_speed, rec.torque_on_bit, lab, mc).statistics()
    assert abs(e["mean"]) < 0.01 and 0.1 < e["std"] < 0.3


def test_a_record_of_sensor_noise_has_no_cycle_frequency():
    # steady drilling seen through 0.03 rad/s of noise: the highest PSD bin of noise is no cycle
    rng = np.random.default_rng(5)
    fs = 1000.0
    t = np.arange(30000) / fs
    noise = 7.5 + 0.03 * rng.standard_normal(t.size)
    assert np.isnan(sig.dominant_frequency(noise, fs))
    lagged = sig.rig_lowpass(noise, fs)  # coloured by the 10 Hz acquisition filter: still no peak
    assert np.isnan(sig.dominant_frequency(lagged, fs))
    cycle = noise + 0.1 * np.sin(2 * np.pi * 2.6 * t)  # a weak oscillation above the same noise
    assert sig.dominant_frequency(cycle, fs) == pytest.approx(2.625, abs=0.13)


def test_cycle_response_reads_phase_and_gain_at_the_cycle_frequency():
    # y lags x by 40 degrees at x's 2.75 Hz peak with half its amplitude; a harmonic and noise around it
    fs = 1000.0
    t = np.arange(0.0, 20.0, 1.0 / fs)
    w = 2.0 * np.pi * 2.75
    rng = np.random.default_rng(3)
    x = np.sin(w * t) + 0.3 * np.sin(2 * w * t) + 0.05 * rng.standard_normal(t.size)
    y = 0.5 * np.sin(w * t - np.radians(40.0)) + 0.05 * rng.standard_normal(t.size)
    r = sig.cycle_response(x, y, fs)
    assert r["frequency_hz"] == pytest.approx(2.75, abs=0.125)
    assert r["phase_deg"] == pytest.approx(-40.0, abs=2.0)
    assert r["gain"] == pytest.approx(0.5, rel=0.03) and r["coherence"] > 0.95
    assert r["in_phase"] == pytest.approx(0.5 * np.cos(np.radians(40.0)), rel=0.04)
    assert np.isnan(sig.cycle_response(x, np.zeros_like(x), fs)["in_phase"])
    assert np.isnan(sig.cycle_response(x[::800], y[::800], 1.25)["frequency_hz"])  # 1-6 Hz above its Nyquist


def test_the_records_top_speed_gives_way_nearly_in_phase_with_the_bit():
    # sample 175: the top encoder's speed in the cycle is 0.42-0.47 of the bit speed's in phase with it
    # (docs/records.md, section 4); an inertia-dominated drive would give a part near zero or negative
    from drillpy.records import rig_comparison
    rec, rep = sample175_cleaned()
    for a in (0.0, 20.0):
        w = rec.select(a, a + 10.0)
        m = rig_comparison.record_metrics(w, rep.stick_threshold_rad_s, float(w.time_s[0]), np.zeros(len(w), bool))
        assert 0.3 < m["top_in_phase"] < 0.6
