"""The break-away torque against the WOB (benchmarks/rig_breakaway_wob.py, issue 28): the rig model's
static torque follows the jack's WOB, which rises over a stick phase; sample 175's does not."""
import numpy as np
import pytest

from _testrig import sample175_cleaned
from drillpy.records import rigsim
from rig_breakaway_wob import exponents, stick_phases
from test_bit_balance import LAW


@pytest.fixture(scope="module")
def phases():
    rec, _ = sample175_cleaned()
    thr = rigsim.stick_threshold(rec)
    # the whole-rig model drillpy analyze calibrates on 0-20 s (rounded, test_bit_balance.py)
    m = rigsim.RigModel(LAW, 0.0303, "rig", 0.25, 0.0186, command_rad_s=17.27, jack_gain_n_rad=181.8,
                        jack_relaxation_s=0.0987, platform_damping=0.75, gj_factor=1.0475,
                        bit_inertia_factor=1.07, coupling_stiffness_nm_rad=41.0)
    return stick_phases(rec, thr), stick_phases(rigsim.simulate_model(m, rec), thr)


def test_the_models_break_away_follows_the_wobs_rise_over_a_stick_and_the_records_does_not(phases):
    record, model = phases
    assert record["breakaway"].size > 40 and model["breakaway"].size > 20
    _, lo_rec, hi_rec = exponents(record, np.random.default_rng(0), 500)
    (_, n_mod), lo_mod, _ = exponents(model, np.random.default_rng(0), 500)
    # Eq. (5.1)'s static torque is linear in the WOB the law sees: the model's exponent on the WOB's
    # rise above its trend is near 1 (1.23 [0.92, 1.49]); the record's interval holds 0 and not 1
    # (-0.16 [-0.64, 0.33])
    assert 0.8 < n_mod < 1.6 and lo_mod[1] > 0.8, (n_mod, lo_mod)
    assert lo_rec[1] < 0.0 < hi_rec[1] < 0.8, (lo_rec, hi_rec)
    # the model's jack raises the WOB over a stick phase more than twice as much as the rig's WOB rises
    assert np.mean(model["rise"]) > 2.0 * np.mean(record["rise"]) > 0.0, (np.mean(model["rise"]), np.mean(record["rise"]))
