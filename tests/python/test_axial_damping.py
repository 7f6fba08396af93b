"""The axial modes' damping of the coupled model (axial.damping, drill/axial_string.hpp): ``distributed``
is D = 2 k M (the distributed damping of Aarsnes and van de Wouw's model), the ratio k / omega_j on
axial mode j; with one elastic axial mode it is the ``modal`` option with zeta = k / omega_1; the
default stays ``modal``; bad input is one error naming the field."""
import numpy as np
import pytest

from drillpy.model.config import load_config
from drillpy.model.simulation import simulate


def _free_free_omega(cfg: dict, n: int) -> np.ndarray:
    """The first n circular frequencies [rad/s] of the string's axial bar elements, top free
    (hook_load): k_e = E A / h [1 -1; -1 1], m_e = rho A h / 6 [2 1; 1 2] (a NumPy oracle of the
    engine's assembly, docs/axial.md)."""
    ks, ms = [], []
    for s in cfg["string"]["sections"]:
        h = s["length_m"] / s["elements"]
        area = np.pi * (s["outer_radius_m"] ** 2 - s["inner_radius_m"] ** 2)
        ks += [s["youngs_modulus_pa"] * area / h] * s["elements"]
        ms += [s["density_kg_m3"] * area * h / 6] * s["elements"]
    nn = len(ks) + 1
    K, M = np.zeros((nn, nn)), np.zeros((nn, nn))
    for e, (k, m) in enumerate(zip(ks, ms)):
        K[e:e + 2, e:e + 2] += k * np.array([[1, -1], [-1, 1]])
        M[e:e + 2, e:e + 2] += m * np.array([[2, 1], [1, 2]])
    L = np.linalg.cholesky(M)
    w2 = np.linalg.eigvalsh(np.linalg.solve(L, np.linalg.solve(L, K).T))
    return np.sqrt(np.clip(np.sort(w2)[:n], 0, None))


def _short(top_speed=12.0, duration=5.0):
    cfg = load_config(preset="rgd-field")
    cfg["operation"]["top_speed_rad_s"] = top_speed
    cfg["simulation"].update(duration_s=duration, transient_s=duration / 2, output_stride=1)
    return cfg


def test_distributed_damping_with_one_elastic_mode_is_the_modal_ratio_k_over_omega():
    # hook_load with two axial modes: the rigid one (undamped in both) and the first elastic one,
    # whose ratio under D = 2 k M is k / omega_1
    k = 2.0
    dist, modal = _short(), _short()
    dist["axial"].pop("damping_ratio")
    dist["axial"].update(modes=2, damping="distributed", damping_rate_per_s=k)
    w1 = _free_free_omega(modal, 2)[1]
    modal["axial"].update(modes=2, damping="modal", damping_ratio=k / w1)
    a, b = simulate(load_config(config=dist)), simulate(load_config(config=modal))
    # the same run to rounding (omega_1 from NumPy and from Eigen agree to ~1e-13)
    assert np.max(np.abs(a.axial.wob - b.axial.wob)) < 1e-7 * 150e3
    assert np.max(np.abs(a.bit_speed - b.bit_speed)) < 1e-7 * 12.0
    # and another k is another run: the damping acts
    modal["axial"]["damping_ratio"] = 2 * k / w1
    c = simulate(load_config(config=modal))
    assert np.max(np.abs(a.axial.wob - c.axial.wob)) > 1e-4 * 150e3


def test_the_default_is_modal_and_an_explicit_modal_is_the_same_run():
    cfg = _short(duration=2.0)
    norm = load_config(config=cfg)
    assert norm["axial"]["damping"] == "modal" and norm["axial"]["damping_ratio"] == 0.05
    assert "damping_rate_per_s" not in norm["axial"]
    explicit = _short(duration=2.0)
    explicit["axial"]["damping"] = "modal"
    a, b = simulate(cfg), simulate(load_config(config=explicit))
    assert np.array_equal(a.axial.wob, b.axial.wob) and np.array_equal(a.bit_speed, b.bit_speed)


@pytest.mark.parametrize("change, field", [
    ({"damping": "viscous"}, "axial.damping"),
    ({"damping": "distributed"}, "axial.damping_rate_per_s"),
    ({"damping": "distributed", "damping_rate_per_s": -1.0}, "axial.damping_rate_per_s"),
    ({"damping_rate_per_s": 1.0}, "axial.damping_rate_per_s"),
    ({"damping": "distributed", "damping_rate_per_s": 1.0, "damping_ratio": 0.05}, "axial.damping_ratio"),
])
def test_bad_damping_is_one_error_naming_the_field(change, field):
    cfg = load_config(preset="rgd-field")
    cfg["axial"].pop("damping_ratio")
    cfg["axial"].update(change)
    with pytest.raises(ValueError, match=field.replace(".", r"\.")):
        load_config(config=cfg)


def test_their_distributed_damping_leaves_a_10_hz_axial_mode_growing_at_their_point():
    """docs/axial.md "Validation": on the string and bit of Aarsnes and van de Wouw's code at their
    30 RPM, 30 m/h, drillpy with their damping D = 2 k M (k = 1/s) grows from steady drilling through
    an axial mode of period 0.1031 s (their code finds it too once its delay line is not diffused),
    while one ratio k / omega_1 on every axial mode, which over-damps the modes above the first, decays."""
    import axial_octave_comparison as B
    from drillpy.model.config import load_config as load
    om, v0 = np.pi, 30 / 3600
    growth = {}
    for damping, am, dt in (("distributed", 80, 1e-4), ("modal", 40, 2.5e-4)):
        r = simulate(load(config=B.drillpy_config(om, v0, 12.0, 0.01, damping=damping, axial_modes=am, dt=dt)))
        t, ob = r.axial.t, r.bit_speed
        m = t >= 2.0
        growth[damping] = B.envelope_growth(t[m] - 2.0, ob[m], om)
        if damping == "distributed":
            assert B.dominant_period(t[m], ob[m]) == pytest.approx(0.1031, rel=0.02)
    assert growth["distributed"] > 0.2  # +0.359/s
    assert growth["modal"] < -0.05
