"""Monte Carlo study of the stochastic model (section 4.2, appendix C) and the ``drillpy mc``
command: statistics against numpy oracles, thread-count and chunk invariance, eta of sample i,
Conv1, stick/slip phases, Ctrl-C, bad input."""
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from drillpy import _core
from drillpy.cli import main
from drillpy.model.config import engine_config, load_config, with_overrides
from drillpy.uncertainty.montecarlo import conv1, phase_study, stochastic_study
from drillpy.uncertainty.process import THESIS_PSD, convert_psd_model, generate, psd_on_grid

SHORT = dict(warmup=20.0, duration=30.0, transient=10.0)  # unit-test durations (cheap)


@pytest.fixture(scope="module")
def cfg():
    return with_overrides(load_config(preset="thesis-field"), modes=10)


@pytest.fixture(scope="module")
def study(cfg):
    return stochastic_study(cfg, [8.0, 16.0, 20.0, 24.0, 27.0], 24, seed=5,
                            psd=convert_psd_model(THESIS_PSD, "two-sided-rad-s"), threads=2,
                            progress=False, **SHORT)


def test_study_statistics_match_numpy(study):
    ss = study.severity
    assert ss.shape == (24, 5)
    np.testing.assert_allclose(study.mean, ss.mean(axis=0), rtol=1e-14)
    np.testing.assert_allclose(study.q05, np.quantile(ss, 0.05, axis=0), rtol=1e-14)
    np.testing.assert_allclose(study.q95, np.quantile(ss, 0.95, axis=0), rtol=1e-14)
    np.testing.assert_array_equal(study.p_exceed, np.mean(ss > 0.5, axis=0))
    # stick-slip at 8 rad/s in every sample, none at 27 rad/s
    assert study.p_exceed[0] == 1.0 and study.p_exceed[-1] == 0.0
    # p05 speed: last crossing of P = 0.05 going up in speed, linear interpolation
    p, sp = study.p_exceed, study.speeds
    k = max(i for i in range(len(sp) - 1) if p[i] > 0.05 >= p[i + 1])
    expect = sp[k] + (p[k] - 0.05) / (p[k] - p[k + 1]) * (sp[k + 1] - sp[k])
    assert study.p05_speed == pytest.approx(expect, rel=1e-12)
    # the deterministic curve is one of the samples with eta = 0: SS > 1 at 8 rad/s, < 0.5 at 24
    assert study.deterministic[0] > 1.0 and study.deterministic[-1] < 0.5
    assert study.eta_std == pytest.approx(0.0502, abs=2e-4)


def test_conv1_is_equation_c1(study):
    ss, sp = study.severity, study.speeds
    integral = np.trapz(ss ** 2, sp, axis=1) if hasattr(np, "trapz") else \
        np.trapezoid(ss ** 2, sp, axis=1)
    expect = np.sqrt(np.cumsum(integral) / np.arange(1, ss.shape[0] + 1))
    np.testing.assert_allclose(study.conv1, expect, rtol=1e-12)
    np.testing.assert_allclose(conv1(ss, sp), expect, rtol=1e-12)


def test_identical_for_one_and_two_threads_and_chunks(cfg, study):
    psd = convert_psd_model(THESIS_PSD, "two-sided-rad-s")
    speeds = study.speeds
    one = stochastic_study(cfg, speeds, 24, seed=5, psd=psd, threads=1, progress=False,
                           deterministic=False, **SHORT)
    np.testing.assert_array_equal(one.severity, study.severity)
    parts = [stochastic_study(cfg, speeds, n, seed=5, psd=psd, first_sample=first, threads=2,
                              progress=False, deterministic=False, **SHORT).severity
             for first, n in ((0, 7), (7, 10), (17, 7))]
    np.testing.assert_array_equal(np.vstack(parts), study.severity)
    other = stochastic_study(cfg, speeds, 2, seed=6, psd=psd, threads=2, progress=False,
                             deterministic=False, **SHORT)
    assert not np.array_equal(other.severity, study.severity[:2])


def test_sample_i_uses_the_generated_realization_i(cfg):
    c = with_overrides(cfg, duration=30.0, transient=10.0)
    _, S = psd_on_grid(THESIS_PSD, 0.05, 30.0)
    mc = _core.MonteCarlo(engine_config(c), S, 0.05, 11, 0.0)
    _, eta = generate(THESIS_PSD, dt=0.05, duration=30.0, samples=3, seed=11, first_sample=4)
    for r in range(3):
        np.testing.assert_array_equal(mc.eta(4 + r), eta[r])


def test_phase_study_collects_cycles(cfg):
    ph = phase_study(cfg, 10.0, seed=2, cycles=40, batch=4, progress=False, **SHORT)
    assert ph.stick.size >= 40
    assert ph.slip.size >= ph.stick.size - ph.samples  # one slip per stick, up to the edges
    # stick-slip cycle of the field string near its first mode (0.13 Hz, 7.6 s): 5-12 s cycles
    cycle = ph.stick.mean() + ph.slip.mean()
    assert 5.0 < cycle < 12.0
    assert np.all(ph.severity > 0.5)
    assert ph.deterministic_stick.size >= 1 and np.all(ph.deterministic_slip > 0)


@pytest.mark.parametrize("kwargs, match", [
    ({"speeds": []}, "the speed grid is empty"),
    ({"speeds": [10.0, -1.0]}, "top speeds must be positive"),
    ({"speeds": [np.nan]}, "top speeds must be positive"),
    ({"samples": 0}, "samples = 0: must be an integer between 1 and 10000000"),
    ({"samples": 10_000_001}, "samples = 10000001"),
    ({"samples": 3.0}, "samples = 3.0"),
    ({"seed": -4}, "seed = -4: must be an integer"),
    ({"seed": 2.5}, "seed = 2.5: must be an integer"),
    ({"seed": 2 ** 64}, "seed = 18446744073709551616"),
    ({"first_sample": -1}, "first_sample = -1"),
    ({"psd": lambda f: f - 1.0}, r"psd\(f = 0 Hz\) = -1: must not be negative"),
    ({"psd": lambda f: np.full_like(f, np.nan)}, "must be a finite number"),
    ({"eta_dt": 0.0}, "eta_dt_s = 0.0"),
    ({"warmup": -1.0}, "montecarlo.warmup_s = -1"),
    ({"duration": -5.0}, "duration_s = -5.0"),
    ({"transient": 40.0}, "simulation.transient_s = 40"),
])
def test_bad_input_is_refused(cfg, kwargs, match):
    args = {"speeds": [10.0, 20.0], "samples": 2, "seed": 1, **SHORT}
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        stochastic_study(cfg, args.pop("speeds"), args.pop("samples"), args.pop("seed"),
                         progress=False, **args)


def test_cli_mc_json(capsys):
    code = main(["mc", "--preset", "thesis-field", "--modes", "10", "--samples", "4",
                 "--speeds", "8:24:3", "--seed", "3", "--warmup", "20", "--duration", "30",
                 "--transient", "10", "--no-progress", "--json"])
    assert code == 0
    res = json.loads(capsys.readouterr().out)
    assert res["samples"] == 4 and res["seed"] == 3
    assert [r["top_speed_rad_s"] for r in res["speeds"]] == [8.0, 16.0, 24.0]
    for r in res["speeds"]:
        assert r["q05"] <= r["mean_ss"] <= r["q95"]
        assert 0.0 <= r["p_ss_gt_0_5"] <= 1.0
    assert "p05_speed_rad_s" in res
    assert res["speeds"][0]["p_ss_gt_0_5"] == 1.0 and res["speeds"][-1]["p_ss_gt_0_5"] == 0.0
    assert res["psd_convention"].startswith("one-sided, per Hz")


def test_cli_mc_refine_brackets_the_5_percent_speed_on_the_same_samples(capsys):
    argv = ["mc", "--preset", "thesis-field", "--modes", "10", "--samples", "12", "--speeds", "12:28:5",
            "--seed", "3", "--warmup", "20", "--duration", "30", "--transient", "10", "--no-progress", "--json"]
    assert main(argv) == 0
    coarse = json.loads(capsys.readouterr().out)
    assert main(argv + ["--refine", "0.25"]) == 0
    fine = json.loads(capsys.readouterr().out)
    lo, hi = fine["p05_speed_bracket_rad_s"]
    assert hi - lo <= 0.5 and lo <= fine["p05_speed_rad_s"] <= hi
    # the bracket lies inside the coarse grid interval that held the crossing
    p = {r["top_speed_rad_s"]: r["p_ss_gt_0_5"] for r in coarse["speeds"]}
    g = sorted(p)
    k = max(i for i in range(len(g) - 1) if p[g[i]] > 0.05 >= p[g[i + 1]])
    assert g[k] <= lo < hi <= g[k + 1]
    assert set(g) <= set(fine["refinement_speeds_rad_s"])
    b = fine["p05_speed_bootstrap"]
    assert b["confidence"] == 0.9 and b["low"] <= b["high"]


@pytest.mark.parametrize("argv, match", [
    (["--samples", "0"], "samples = 0"),
    (["--samples", "ten"], "samples = 'ten': must be an integer"),
    (["--seed", "1.5"], "seed = '1.5': must be an integer"),
    (["--seed", "-3"], "seed = -3: must be an integer"),
    (["--speeds", ""], "--speeds = '': use start:stop:num"),
    (["--speeds", "6:27:0"], "--speeds = '6:27:0'"),
    (["--eta-dt", "-0.1"], "eta_dt_s = -0.1"),
    (["--psd-model", "0.27,-7.6,-3.13"], "--psd-model = '0.27,-7.6,-3.13': use f0,A0,a,b"),
    (["--psd-model", "0,-7.6,-3.13,-11.67"], "psd.f0_hz = 0"),
])
def test_cli_mc_bad_input_one_line_exit_2(capsys, argv, match):
    code = main(["mc", "--preset", "thesis-field", "--no-progress", "--json", *argv])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert len(err) == 1 and err[0].startswith("drillpy: error: ")
    assert match in err[0]


def test_cli_mc_psd_table(tmp_path, capsys):
    table = tmp_path / "psd.csv"
    table.write_text("# f_hz,S\n0,1e-3\n1,1e-3\n2,-1e-4\n")
    code = main(["mc", "--preset", "thesis-field", "--psd-table", str(table), "--samples", "2",
                 "--no-progress", "--json"])
    assert code == 2
    assert "psd.table.S[2] = -0.0001" in capsys.readouterr().err


def _cpu_seconds(pid: int) -> float:
    """User + system CPU time of a process and its threads [s] (Linux /proc)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def test_ctrl_c_stops_a_study_quickly():
    """SIGINT during a long study: the engine stops at the next chunk boundary, exit code 130."""
    p = subprocess.Popen([sys.executable, "-m", "drillpy", "mc", "--preset", "thesis-field",
                          "--samples", "5000", "--threads", "2", "--no-progress", "--json"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         # a shell's background job inherits SIGINT ignored: give the study the
                         # disposition an interactive user's process has
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    # wait until the study runs: CPU time past what the imports take (wall time would not do on a
    # loaded machine, and no bar is drawn without a terminal)
    deadline = time.monotonic() + 300.0
    while _cpu_seconds(p.pid) < 4.0 and p.poll() is None and time.monotonic() < deadline:
        time.sleep(0.1)
    t0 = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=60)
    assert p.returncode == 130, err.decode()
    assert time.monotonic() - t0 < 20.0
    assert b"interrupted" in err and out == b""
