"""The loop's independent fits side by side (issue 33, drillpy.loop.side_by_side): the tasks'
results in order and the engine's cores shared by the tasks running; a refit and a whole loop run
give the same numbers, bit for bit, on one thread (one task after the other) as on two (side by
side)."""
from __future__ import annotations

import dataclasses
import threading
import time

import pytest

from drillpy import loop as L
from drillpy.loop import fitting as F
from drillpy.loop import side_by_side as S
from drillpy.loop.run import analysis_config
from drillpy.loop.synthetic import declared_config, synthetic_record
from drillpy.model.config import normalize

RATE_HZ, DT_S = 500.0, 2e-4


def test_tasks_return_in_order_and_share_the_cores():
    """Two tasks on two cores: each engine call inside gets one thread while both run, both once
    the other has finished; results in the tasks' order; outside, the loop's setting unchanged."""
    opt = L.LoopOptions(threads=2)
    seen, both_running, both_read = {}, threading.Barrier(2), threading.Barrier(2)

    def task(x, o):
        both_running.wait(timeout=10)
        seen[x] = S.engine_threads(o.threads)
        both_read.wait(timeout=10)
        if x == "slow":  # wait for the other task to end: then this one gets both cores
            deadline = time.monotonic() + 10.0
            while S.engine_threads(o.threads) != 2 and time.monotonic() < deadline:
                time.sleep(0.005)
            seen["alone"] = S.engine_threads(o.threads)
        return x * 2

    assert S.task_map(task, ["slow", "fast"], opt) == ["slowslow", "fastfast"]
    assert seen == {"slow": 1, "fast": 1, "alone": 2}
    assert S.engine_threads(0) == 0 and S.engine_threads(3) == 3


def test_one_thread_runs_the_tasks_in_turn_and_nested_tasks_do_not_fork():
    """threads=1: one task after the other in the caller's thread; a task_map inside a task runs its
    own tasks in that task's thread; the first task's error reaches the caller."""
    main = threading.get_ident()
    assert S.task_map(lambda x, o: threading.get_ident(), [1, 2, 3], L.LoopOptions(threads=1)) == [main] * 3

    def outer(x, o):
        me = threading.get_ident()
        return S.task_map(lambda y, _: threading.get_ident() == me, [x, x], o)

    assert S.task_map(outer, [1, 2], L.LoopOptions(threads=2)) == [[True, True], [True, True]]

    def fails(x, o):
        if x:
            raise ValueError(f"task {x}")
        return x
    with pytest.raises(ValueError, match="task 1"):
        S.task_map(fails, [0, 1, 2], L.LoopOptions(threads=2))


@pytest.fixture(scope="module")
def record():
    return synthetic_record({"sensor_lag": {}}, duration_s=8.0, seed=6, fs_hz=RATE_HZ)


def test_a_refit_side_by_side_is_the_refit_in_turn_bit_for_bit(record):
    """refit's two starts (the law refitted, the model's own values) on two threads and on one:
    the same parameters and intervals, bit for bit."""
    opt = L.LoopOptions(rate_hz=RATE_HZ, dt_s=DT_S, nfev_per_parameter=6, threads=1)
    cfg = normalize(declared_config())
    data = L.prepare(record, cfg, opt)
    m = F.declared_model(analysis_config(cfg, data.dt, opt.dt_s), data, opt)
    a, ca = F.refit(m, data, opt)
    b, cb = F.refit(m, data, dataclasses.replace(opt, threads=2))
    assert a.law == b.law and a.damping_ratios == b.damping_ratios and a.gj_factor == b.gj_factor
    assert a.effects == b.effects and ca == cb


def test_a_loop_run_side_by_side_is_the_run_in_turn_bit_for_bit(record):
    """A loop run with candidates, the damping hold's grid and refits: the same steps, rounds and
    errors on two threads (side by side) as on one (in turn)."""
    runs = []
    for threads in (1, 2):
        opt = L.LoopOptions(rate_hz=RATE_HZ, dt_s=DT_S, nfev_per_parameter=6, max_steps=2, discovery=False,
                            effects=("sensor_lag", "viscous_damping", "static_friction"), threads=threads)
        runs.append(L.run_loop(record, declared_config(), opt, log=lambda *a: None))
    a, b = runs
    assert [(s.action, s.effect, s.error_before, s.error_after) for s in a.steps] == \
        [(s.action, s.effect, s.error_before, s.error_after) for s in b.steps]
    assert a.rounds == b.rounds and len(a.rounds) >= 1 and len(a.rounds[0]) >= 2
    assert a.baseline.E_test == b.baseline.E_test and a.final.E_test == b.final.E_test
    assert a.final.model.cfg == b.final.model.cfg
