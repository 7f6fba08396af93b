"""Convergence orders: FE frequencies (order 2) and the two time schemes (orders 1 and 2)."""
import numpy as np

import drillpy
from drillpy.model.convergence import observed_orders, space_study, time_study

FIELD = drillpy.load_config(preset="thesis-field")


def test_observed_orders_of_exact_power_laws():
    h = [0.4, 0.2, 0.1]
    np.testing.assert_allclose(observed_orders(h, [3 * x ** 2 for x in h]), [2.0, 2.0])


def test_fe_frequencies_converge_at_order_two():
    s = space_study(FIELD, elements=(25, 50, 100, 200))
    np.testing.assert_allclose(s["exact_hz"][:2], [0.1317, 0.4199], atol=1e-4)
    assert all(1.9 < o < 2.1 for o in s["orders"])


def test_time_schemes_orders_in_the_slip_regime():
    t = time_study(FIELD, 30.0, 4.0, rigid_start=True, dts=(2e-3, 1e-3, 5e-4))
    assert t["reference_min_bit_speed"] > 1.0  # slipping throughout: smooth solution
    assert all(0.85 < o < 1.3 for o in t["modified_euler"]["orders"])
    assert all(1.8 < o < 2.2 for o in t["bdf2"]["orders"])


def test_branch_check_runs_dt_and_half_and_flags_by_its_tolerance():
    from drillpy.model.convergence import branch_check
    cfg = drillpy.with_overrides(FIELD, scheme="exact_modal", dt=1e-2, duration=40.0, transient=20.0)
    b = branch_check(cfg, 10.0, threads=1)
    assert b["dt_s"] == [1e-2, 5e-3]
    assert all(s > 1.0 for s in b["severity"]) and all(f > 0 for f in b["stick_fraction"])  # stick-slip at both
    assert 0 < b["relative_difference"] < 0.05 and not b["flagged"]
    # the same runs against a tolerance below their difference are flagged
    assert branch_check(cfg, 10.0, rel_tol=0.1 * b["relative_difference"], threads=1)["flagged"]
    # above the threshold neither run sticks
    fast = branch_check(cfg, 30.0, threads=1)
    assert all(f == 0 for f in fast["stick_fraction"]) and not fast["flagged"]
