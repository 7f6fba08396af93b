"""The coupled model (axial.type = rgd) in the limit where its bit torque is a constant: the torsional
engine with T = T0 sign(Omega) (benchmarks/axial_torsional_limit.py, docs/axial.md "Validation").

A rigid axial string would not do: with a feed top the depth of cut is then N V0 t_N(t), a delay on
the bit's rotation, so the RGD torque a^2 eps d / 2 + T_f is a constant only when its cutting part
vanishes against the contact part T_f. The difference between the two models is then first order in
the cutting share T_c / T0: the torque differs by exactly T_c (d / d0 - 1) and the bit speed by an
amount proportional to T_c / T0."""
import pytest

from axial_torsional_limit import compare, coupled_config


@pytest.fixture(scope="module")
def runs():
    return {s: compare(s, duration=10.0) for s in (1e-3, 1e-4)}


def test_the_torque_differs_by_the_cutting_torques_own_swing(runs):
    for r in runs.values():
        # T_coupled - T0 = T_c (d / d0 - 1) while the bit turns forwards; the constant law gives T0
        assert r["dtorque"] <= r["share"] * r["d_dev"] * (1.0 + 1e-3)
        assert r["dtorque"] >= 0.9 * r["share"] * r["d_dev"]
        assert 0.005 < r["d_dev"] < 0.02  # the depth of cut moves with the 1 % disturbances


def test_the_difference_is_first_order_in_the_cutting_share(runs):
    a, b = runs[1e-3], runs[1e-4]
    share_ratio = a["share"] / b["share"]
    assert share_ratio == pytest.approx(10.0, rel=0.01)
    # a tenth of the cutting torque, a tenth of the difference (to the second-order remainder)
    assert a["dspeed"] / b["dspeed"] == pytest.approx(share_ratio, rel=0.05)
    assert a["dtorque"] / b["dtorque"] == pytest.approx(share_ratio, rel=0.05)
    for r in (a, b):
        assert r["dspeed"] <= 0.05 * r["share"]  # 0.029 T_c / T0 on this string
        assert r["ss_coupled"] == pytest.approx(r["ss_torsional"], abs=2.0 * r["share"])


def test_no_config_stiffens_the_axial_string_alone():
    """G = E / (2 (1 + nu)) with nu < 0.5: raising E with G fixed is refused naming the field."""
    from drillpy.model.config import load_config
    cfg = coupled_config(1.0, 1.0)
    sec = cfg["string"]["sections"][0]
    G = sec["youngs_modulus_pa"] / (2.0 * (1.0 + sec["poisson_ratio"]))
    sec["youngs_modulus_pa"] = 3.5 * G
    sec["poisson_ratio"] = 3.5 / 2.0 - 1.0
    with pytest.raises(ValueError, match="poisson_ratio"):
        load_config(config=cfg)


def test_the_octave_comparison_skips_without_the_matlab_folder(tmp_path):
    """benchmarks/axial_octave_comparison.py fetches nothing: no folder (or no octave), a message, exit 0."""
    import subprocess
    import sys
    from pathlib import Path
    script = Path(__file__).resolve().parents[2] / "benchmarks" / "axial_octave_comparison.py"
    r = subprocess.run([sys.executable, str(script), "--matlab-dir", str(tmp_path / "absent")],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("skipped: ")


@pytest.fixture(scope="module")
def exact_runs():
    return {s: compare(s, duration=10.0, scheme="exact_modal", dt=5e-3) for s in (1e-3, 1e-4)}


def test_the_exact_modal_step_reproduces_the_torsional_exact_modal_engine(exact_runs):
    """simulation.scheme = exact_modal at 5 ms on both: the coupled exact step (axial_torsional.hpp)
    against the torsional engine's (exact_modal.hpp) with T = T0 sign(Omega). As on the modified Euler,
    the torque differs by the cutting torque's own swing and both differences scale with the cutting
    share (first order in it), so the two steps are the same scheme in the constant-torque limit."""
    a, b = exact_runs[1e-3], exact_runs[1e-4]
    for r in (a, b):
        assert r["dtorque"] <= r["share"] * r["d_dev"] * (1.0 + 1e-3)
        assert r["dtorque"] >= 0.9 * r["share"] * r["d_dev"]
        assert 0.005 < r["d_dev"] < 0.02
        assert r["dspeed"] <= 0.05 * r["share"]
        assert r["ss_coupled"] == pytest.approx(r["ss_torsional"], abs=2.0 * r["share"])
    share_ratio = a["share"] / b["share"]
    assert a["dspeed"] / b["dspeed"] == pytest.approx(share_ratio, rel=0.05)
    assert a["dtorque"] / b["dtorque"] == pytest.approx(share_ratio, rel=0.05)


@pytest.fixture(scope="module")
def motor_runs():
    return {s: compare(s, duration=10.0, drive="motor") for s in (1e-3, 1e-4)}


def test_the_motor_drive_reproduces_the_torsional_engines_motor(motor_runs):
    """The rig's open-loop motor (drives/motor.hpp) on both models, J_m 2000 kg m^2 and a slope that
    droops the top by 20 % under T0: both start at their own drooped speed, Omega_c - T0 / c_m = 3.2
    rad/s, and differ, top speed included, to first order in the cutting share as with the ideal drive."""
    a, b = motor_runs[1e-3], motor_runs[1e-4]
    for r in (a, b):
        # the droop, not the command (the string's top torque of 20 modes is 1.3 % below T0: 3.21 rad/s)
        assert r["top_mean"] == pytest.approx(0.8 * 4.0, rel=5e-3)
        assert r["dtorque"] <= r["share"] * r["d_dev"] * (1.0 + 1e-3)
        assert r["dspeed"] <= 0.05 * r["share"]
        assert r["dtop"] <= 0.01 * r["share"]
        assert r["ss_coupled"] == pytest.approx(r["ss_torsional"], abs=2.0 * r["share"])
    share_ratio = a["share"] / b["share"]
    assert a["dspeed"] / b["dspeed"] == pytest.approx(share_ratio, rel=0.05)
    assert a["dtop"] / b["dtop"] == pytest.approx(share_ratio, rel=0.1)
