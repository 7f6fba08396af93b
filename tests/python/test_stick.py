"""The stick rule has one home (records/stick.py) and agrees with the engine's."""
import numpy as np
import pytest

from drillpy.model.config import load_config, preset_names
from drillpy.records.stick import STICK_FRACTION, stick_threshold


@pytest.mark.parametrize("preset", preset_names())
def test_python_rule_is_the_engine_default(preset):
    assert load_config(preset=preset)["metrics"]["stick_threshold_fraction"] == STICK_FRACTION


def test_threshold_is_the_fraction_of_the_median_top_speed_ignoring_gaps():
    top = np.array([10.0, 12.0, np.nan, 11.0, -np.inf, 11.0])
    assert stick_threshold(top) == pytest.approx(0.05 * 11.0)
    assert stick_threshold(-top, 0.1) == pytest.approx(1.1)      # the sense of rotation does not matter
    assert np.isnan(stick_threshold([np.nan, np.nan]))
