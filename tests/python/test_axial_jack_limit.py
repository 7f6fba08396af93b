"""The rig's jack (one WOB state, drill/axial.hpp) as the limit of the coupled model (axial.type = rgd,
axial.top = jack) whose cut remembers longer than the jack relaxes (benchmarks/axial_jack_limit.py,
docs/axial.md "The jack as a limit of the coupled model")."""
import pytest

from axial_jack_limit import compare


@pytest.fixture(scope="module")
def one_edge():
    return compare(1, duration=30.0)


def test_the_jack_state_gives_the_coupled_models_long_run_metrics_when_the_cut_remembers_longer(one_edge):
    r = one_edge
    assert r["t_n"] > 5.0 * 0.1  # the cut's memory, one revolution, against the jack's 0.1 s
    c, j = r["coupled"], r["jack"]
    assert j["ss"] == pytest.approx(c["ss"], rel=0.03)
    assert j["stick"] == pytest.approx(c["stick"], rel=0.1)
    assert abs(j["fc"] - c["fc"]) <= 0.125 + 1e-9  # one Welch bin
    assert j["wob_mean"] == pytest.approx(c["wob_mean"], rel=0.02)
    assert j["wob_sd"] == pytest.approx(c["wob_sd"], rel=0.15)
    assert j["top"] == pytest.approx(c["top"], rel=0.03)


def test_the_delayed_cut_follows_the_bit_speed_more_closely_than_the_jack_state(one_edge):
    """The WOB's phase differs: RGD's t_N swings with the bit's past speed under stick-slip, where the jack
    integrates the lag; both swing the WOB against the bit speed."""
    c, j = one_edge["coupled"], one_edge["jack"]
    assert c["corr"] < j["corr"] - 0.2
    assert j["corr"] < -0.2
