"""The axial-torsional model (axial.type = rgd, drill/axial_torsional.hpp) from Python and the CLI:
the RunReport's axial channels, the summary's WOB/ROP/bounce metrics, sweep and map over top speed
and hook load, and studies it does not implement refused with one line naming axial.type."""
import json

import numpy as np
import pytest

from drillpy.model.config import load_config
from drillpy.model.simulation import law_torque, simulate

from conftest import run_cli


def _short(duration=4.0):
    cfg = load_config(preset="rgd-field")
    cfg["simulation"].update(duration_s=duration, transient_s=duration / 2)
    return cfg


def test_simulate_reports_the_axial_channels():
    r = simulate(_short())
    ax = r.axial
    assert ax is not None and ax.present
    assert ax.t.shape == ax.wob.shape == ax.rop.shape == ax.depth_of_cut.shape == ax.delay.shape
    assert np.all(np.isfinite(ax.wob)) and np.all(ax.wob >= 0.0)
    # the run starts in RGD's steady drilling: 150 kN = a zeta eps d + a l sigma
    a, zeta, eps, wear, sigma = 0.108, 0.6, 60e6, 0.011, 60e6
    d0 = (150e3 - a * wear * sigma) / (a * zeta * eps)
    assert ax.steady_depth == pytest.approx(d0, rel=1e-12)
    assert ax.steady_rop == pytest.approx(4.0 * d0 / (2 * np.pi), rel=1e-12)
    assert ax.wob[0] == pytest.approx(150e3, rel=1e-9)
    assert ax.delay[0] == pytest.approx(2 * np.pi / (4 * 4.0), rel=1e-9)  # t_N = 2 pi / (N Omega)
    s = r.summary()
    for key in ("mean_wob_n", "wob_std_n", "mean_rop_m_s", "rop_std_m_s", "bounce_fraction", "steady_wob_n"):
        assert key in s
    assert s["steady_wob_n"] == pytest.approx(150e3)


def test_a_bit_thrown_up_leaves_the_rock_with_zero_wob():
    cfg = _short(3.0)
    cfg["simulation"].update(output_stride=1, transient_s=0.0)
    cfg["axial"]["disturbance"] = 50.0  # the bit's axial speed (1 - 50) V0 at the start: upwards
    r = simulate(cfg)
    ax = r.axial
    off = ax.depth_of_cut <= 0.0
    assert off.sum() > 10 and ax.bounce_fraction > 0.0
    assert np.all(ax.wob[off] == 0.0) and np.all(r.torque_on_bit[off] == 0.0)
    assert np.all(np.isfinite(ax.wob)) and np.all(np.isfinite(r.bit_speed))
    assert ax.wob[-1] > 0.0  # it lands and cuts again


def test_torsional_models_have_no_axial_report():
    cfg = load_config(preset="thesis-rig")
    cfg["simulation"].update(duration_s=1.0, transient_s=0.5)
    r = simulate(cfg)
    assert r.axial is None
    assert "mean_wob_n" not in r.summary()


def test_config_round_trips_and_refuses_a_law():
    cfg = load_config(preset="rgd-field")
    assert "law" not in cfg and cfg["axial"]["type"] == "rgd"
    assert load_config(config=cfg) == cfg
    bad = dict(cfg, law=load_config(preset="thesis-field")["law"])
    with pytest.raises(ValueError, match=r"config.law = .*axial.type = rgd"):
        load_config(config=bad)
    assert load_config(config=cfg)["axial"]["torque"] == "rgd"  # RGD's torque law by default


def test_the_thesis_law_takes_the_torque_on_the_axial_wob():
    """axial.torque = "law": the torque on bit is the "law" block's at the bit speed with the WOB the
    axial state W (T_law scaling with W / wob_ref_n); steady drilling keeps RGD's W0 and V0 and carries
    T_law(Omega; W0). An unknown value, or "law" without a law block, is refused naming axial.torque."""
    cfg = _short(2.0)
    law = load_config(preset="thesis-field")["law"]
    cfg["axial"].update(torque="law", disturbance=0.0)
    cfg["law"] = law
    cfg["simulation"]["start"] = "steady"
    cfg = load_config(config=cfg)
    assert cfg["axial"]["torque"] == "law" and cfg["law"] == law
    r = simulate(cfg)
    ax = r.axial
    assert ax.steady_wob == pytest.approx(150e3, rel=1e-12)
    T0 = float(law_torque(law, 4.0, 0.0, ax.steady_wob)[0])
    assert ax.steady_torque == pytest.approx(T0, rel=1e-12)
    assert T0 == pytest.approx(float(law_torque(law, 4.0)[0]) * 150e3 / law["wob_ref_n"], rel=1e-12)
    # the run starts in steady drilling with the bit lagging the top by 1 % (the torsional disturbance)
    assert ax.wob[0] == pytest.approx(150e3, rel=1e-9)
    assert np.allclose(r.torque_on_bit, T0, rtol=0.02) and np.allclose(ax.wob, 150e3, rtol=0.01)
    with pytest.raises(ValueError, match="axial.torque"):
        load_config(config=dict(cfg, axial=dict(cfg["axial"], torque="xyz")))
    bare = {k: v for k, v in cfg.items() if k != "law"}
    with pytest.raises(ValueError, match="axial.torque"):
        load_config(config=bare)


def test_cli_simulate_prints_wob_rop_and_bounce_beside_ss():
    r = run_cli("simulate", "--preset", "rgd-field", "--json")
    assert r.returncode == 0, r.stderr
    s = json.loads(r.stdout)
    assert s["severity"] > 0.5  # stick-slip at the preset's 4 rad/s and 150 kN
    assert s["bounce_fraction"] >= 0.0 and s["wob_std_n"] > 0.0
    r = run_cli("simulate", "--preset", "rgd-field")
    assert r.returncode == 0, r.stderr
    assert "WOB = " in r.stdout and "ROP = " in r.stdout and "bit bounce fraction" in r.stdout


def test_cli_simulate_writes_the_axial_channels(tmp_path):
    r = run_cli("simulate", "--preset", "rgd-field", "--duration", "2", "--out", str(tmp_path / "o"))
    assert r.returncode == 0, r.stderr
    text = (tmp_path / "o" / "axial.csv").read_text().splitlines()
    assert "time_s,wob_N,rop_m_s,bit_position_m,depth_of_cut_m,delay_s" in text
    data = np.loadtxt(tmp_path / "o" / "axial.csv", delimiter=",", comments="#", skiprows=text.index(
        "time_s,wob_N,rop_m_s,bit_position_m,depth_of_cut_m,delay_s") + 1)
    assert data.shape[1] == 6 and data[0, 1] == pytest.approx(150e3, rel=1e-6)
    assert (tmp_path / "o" / "axial.png").stat().st_size > 10_000  # WOB, ROP and depth of cut drawn


def test_sweep_runs_the_coupled_model_as_simulate_does():
    """sweep on the axial-torsional model: each grid point is the run simulate makes (same start,
    same engine path), whatever the thread count."""
    from drillpy.model.simulation import sweep_severity
    cfg = _short(6.0)
    speeds = [3.0, 6.0]
    ss = sweep_severity(cfg, speeds, progress=False, threads=2)
    assert np.array_equal(ss, sweep_severity(cfg, speeds, progress=False, threads=1))
    for om, s in zip(speeds, ss):
        c = _short(6.0)
        c["operation"]["top_speed_rad_s"] = om
        assert s == simulate(c).severity


def test_map_over_hook_load_stick_slips_more_under_a_heavier_load_and_less_at_a_higher_speed():
    """The RPM x hook-load map of the RGD field string (20 s runs): at a fixed speed a heavier
    load (a deeper cut, a steeper RGD torque) raises SS; at a fixed load a faster top lowers it."""
    from drillpy.model.simulation import stability_map
    cfg = _short(20.0)
    speeds, wobs = np.array([3.1, 9.4]), np.array([100e3, 200e3])  # 30 and 90 RPM; 100 and 200 kN
    ss = stability_map(cfg, speeds, wobs, progress=False)
    assert ss.shape == (2, 2)
    assert ss[1, 0] > ss[0, 0] + 0.5  # 30 RPM: 100 kN -> 200 kN
    assert ss[1, 1] < 0.5 * ss[1, 0]  # 200 kN: 30 RPM -> 90 RPM


def test_a_wob_grid_with_a_constant_feed_is_refused_naming_the_field():
    from drillpy.model.simulation import stability_map
    cfg = _short()
    cfg["axial"]["top"] = "feed"
    cfg["axial"]["rop_m_s"] = 0.006
    del cfg["operation"]["wob_n"]
    with pytest.raises(ValueError, match="sweep.wobs_n"):
        stability_map(cfg, [3.0], [100e3, 200e3], progress=False)


def test_monte_carlo_runs_the_coupled_model_with_the_stochastic_torque():
    """mc on the axial-torsional model: eta of Eq. (4.1) scales the RGD torque bounds; the eta = 0
    reference is the deterministic sweep itself; samples are the same numbers on 1 and 2 threads; a
    torque that fluctuates by tens of per cent changes SS; the warm start is 0 (steady drilling)."""
    from drillpy.model.simulation import sweep_severity
    from drillpy.uncertainty.montecarlo import stochastic_study
    from drillpy.uncertainty.process import PsdModel
    cfg = _short(8.0)
    speeds = [3.0, 9.0]
    psd = PsdModel(2.0, -3.22, -3.0, -1.14)  # flat to 2 Hz, then f^-3: eta std about 0.35
    kw = dict(psd=psd, duration=8.0, transient=4.0, progress=False)
    a = stochastic_study(cfg, speeds, 4, 7, threads=2, **kw)
    b = stochastic_study(cfg, speeds, 4, 7, threads=1, deterministic=False, **kw)
    assert np.array_equal(a.severity, b.severity)
    assert a.settings["warmup_s"] == 0.0 and a.eta_std > 0.2
    assert np.array_equal(a.deterministic, sweep_severity(cfg, speeds, progress=False))
    assert np.max(np.abs(a.severity - a.deterministic[None, :])) > 0.05
    with pytest.raises(ValueError, match="montecarlo.warmup_s"):
        stochastic_study(cfg, speeds, 2, 7, warmup=5.0, **kw)


def test_stored_coupled_monte_carlo_is_the_same_bits_for_any_chunk(tmp_path):
    """mc of the axial-torsional model through a study store (``drillpy mc --out``): the samples do
    not depend on how the study is cut into blocks, and equal the in-memory study's."""
    from drillpy.study import compute_study, mc_study
    from drillpy.uncertainty.montecarlo import stochastic_study
    from drillpy.uncertainty.process import PsdModel
    cfg = _short(6.0)
    psd = PsdModel(2.0, -3.22, -3.0, -1.14)
    kw = dict(psd=psd, duration=6.0, transient=3.0)
    ref = stochastic_study(cfg, [3.0, 9.0], 5, 11, threads=2, progress=False, **kw).severity
    for chunk in (1, 3):
        data = compute_study(mc_study(cfg, [3.0, 9.0], 5, 11, **kw), tmp_path / str(chunk), chunk=chunk,
                             threads=2, progress=False)
        assert np.array_equal(data["severity"], ref)
        assert data["done"].all()


def test_mse_of_steady_drilling_is_the_rock_energy_plus_wob_and_friction_terms():
    """Teale's MSE = W / A + T Omega / (A V). At RGD's steady drilling the cutting part gives the
    intrinsic specific energy eps exactly (T_c = a^2 eps d / 2, V = Omega d / 2 pi), the wear flats
    add gamma mu l sigma / d, the thrust W / (pi a^2). A run that stays near steady drilling (12 rad/s,
    SS below 0.05) measures the same MSE within 1 %."""
    cfg = _short(20.0)
    cfg["operation"]["top_speed_rad_s"] = 12.0
    r = simulate(cfg)
    ax = r.axial
    a, eps, wear, sigma, gamma, mu = 0.108, 60e6, 0.011, 60e6, 1.0, 0.6
    d0, W0 = ax.steady_depth, ax.steady_wob
    assert ax.steady_mse == pytest.approx(eps + gamma * mu * wear * sigma / d0 + W0 / (np.pi * a * a), rel=1e-9)
    assert r.severity < 0.05
    assert ax.mse == pytest.approx(ax.steady_mse, rel=0.01)
    assert r.summary()["mse_pa"] == ax.mse


@pytest.mark.parametrize("disturbance", [0.0, 0.01, 0.05, 0.2, 1.0])
def test_the_exact_scheme_with_the_hysteretic_law_on_the_wob_reaches_the_fine_cycle_from_any_start_at_1_ms(disturbance):
    """The thesis's hysteretic law (Eqs. 3.2-3.3, beta1 = 0.14) on the axial WOB of the rgd-field string at
    8 rad/s stick-slips (SS about 1.22-1.24) from every start on the modified Euler at 0.1 ms; the exact
    modal scheme reaches that cycle from every start at 1 ms (at 2.5 ms it leaves it from some starts for
    the model's other regime, with no stick, which the model has for beta1 between about 0.145 and
    0.155: docs/axial.md, "The time step")."""
    import sys
    from pathlib import Path
    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
    from axial_scheme_convergence import config
    out = {}
    for scheme, dt in (("modified_euler", 1e-4), ("exact_modal", 1e-3)):
        c = config("law", scheme, dt, 60.0)
        c["axial"]["disturbance"] = disturbance
        out[scheme] = simulate(load_config(config=c), record=False).summary()
    ref, got = out["modified_euler"], out["exact_modal"]
    assert ref["stick_fraction"] > 0.05 and got["stick_fraction"] > 0.05
    assert got["severity"] == pytest.approx(ref["severity"], rel=0.05)
