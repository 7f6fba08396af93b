"""Synthetic validation of ``drillpy loop``: records of the test-rig model with known effects.

For every case (injected effects with their parameters, seed) a synthetic record is generated
(:func:`drillpy.synthetic.synthetic_record`, measurement noise included), the loop runs from the
declared model without any effect (:func:`drillpy.synthetic.declared_config`), and one line of the
table injected -> found -> error before -> error after (validation part) is printed, with the
first step's error ratio. The cases are those of tests/python/test_loop.py.

    PYTHONPATH=python python3 benchmarks/loop_synthetic.py            # the whole table (about 2 min)
    PYTHONPATH=python python3 benchmarks/loop_synthetic.py --markdown # as a Markdown table
"""
from __future__ import annotations

import argparse
import sys
import time

from drillpy.loop import LoopOptions, run_loop
from drillpy.synthetic import declared_config, synthetic_record

#: (injected effects with parameters, seed): two parameter sets per effect, no effect, two effects.
CASES_ALL = [
    ({}, 1), ({}, 2), ({}, 3),
    ({"bit_hysteresis": {"beta1": 0.2, "beta2": 0.005}}, 1),
    ({"bit_hysteresis": {"beta1": 0.3, "beta2": 0.003}}, 2),
    ({"wob_coupling": {"gain": 1.0}}, 1),
    ({"wob_coupling": {"gain": 0.7}}, 2),
    ({"top_drive_dynamics": {"slope_nms_rad": 0.25, "inertia_kg_m2": 0.02}}, 1),
    ({"top_drive_dynamics": {"slope_nms_rad": 0.3, "inertia_kg_m2": 0.03}}, 2),
    ({"sensor_lag": {"lowpass_hz": 10.0}}, 1),
    ({"sensor_lag": {"lowpass_hz": 6.0}}, 2),
    ({"torque_fluctuation": {"std": 0.15, "f0_hz": 0.25}}, 1),
    ({"torque_fluctuation": {"std": 0.2, "f0_hz": 0.2}}, 2),
    ({"viscous_damping": {"bit_viscous_nms": 0.03}}, 1),
    ({"viscous_damping": {"bit_viscous_nms": 0.02}}, 2),
    ({"top_drive_dynamics": {}, "wob_coupling": {}}, 4),
    ({"sensor_lag": {}, "bit_hysteresis": {}}, 5),
    ({"viscous_damping": {}, "wob_coupling": {}}, 6),
    ({"torque_fluctuation": {}, "top_drive_dynamics": {}}, 7),
]
CASES = CASES_ALL
#: Record length [s], rate [Hz] and engine step of the loop [s] of the cases.
DURATION_S, RATE_HZ, LOOP_DT_S = 12.0, 500.0, 2e-4


_DONE: dict = {}


def run_case(effects: dict, seed: int) -> dict:
    """Generate the record of a case, run the loop, summarize (cached: a case runs once)."""
    key = (repr(effects), seed)
    if key not in _DONE:
        _DONE[key] = _run(effects, seed)
    return _DONE[key]


def _run(effects: dict, seed: int) -> dict:
    rec = synthetic_record(effects, duration_s=DURATION_S, seed=seed, fs_hz=RATE_HZ)
    res = run_loop(rec, declared_config(), LoopOptions(rate_hz=RATE_HZ, dt_s=LOOP_DT_S), log=lambda *a: None)
    found = [s["effect"] for s in res.steps]
    first = res.steps[0] if res.steps else None
    if not effects:  # no missing effect: the loop adds nothing
        ok = not found
    elif len(effects) == 1:  # that effect first, its error after at most 0.6 of the error before
        ok = first is not None and first["effect"] in effects and first["error_after"] <= 0.6 * first["error_before"]
    else:  # every effect found
        ok = set(effects) <= set(found)
    return {"injected": effects, "seed": seed, "found": found, "baseline": res.baseline.E_test,
            "first_after": first["error_after"] if first else res.baseline.E_test, "final": res.final.E_test,
            "params": {s["effect"]: s["evidence"]["parameters"] for s in res.steps}, "ok": ok}


def _params(p: dict) -> str:
    return ", ".join(f"{k} {v:.3g}" for k, v in p.items() if isinstance(v, float))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--markdown", action="store_true")
    ap.add_argument("--only", help="run only the cases whose injected effects contain this name ('none': no effect)")
    a = ap.parse_args(argv)
    cases = [c for c in CASES if a.only is None or (a.only in c[0]) or (a.only == "none" and not c[0])]
    if a.markdown:
        print("| injected (parameters) | seed | found (in order) | E before | E after step 1 | ratio | E final | "
              "fitted | pass |")
        print("|---|---:|---|---:|---:|---:|---:|---|---|")
    ok_all = True
    for eff, seed in cases:
        t = time.time()
        r = run_case(eff, seed)
        ok_all &= r["ok"]
        inj = "; ".join(f"{k} ({_params(v) or 'defaults'})" for k, v in eff.items()) or "none"
        fitted = "; ".join(f"{k}: {_params(v)}" for k, v in r["params"].items()) or "-"
        ratio = r["first_after"] / r["baseline"]
        if a.markdown:
            print(f"| {inj} | {seed} | {', '.join(r['found']) or 'none'} | {r['baseline']:.3f} | {r['first_after']:.3f} | "
                  f"{ratio:.2f} | {r['final']:.3f} | {fitted} | {'yes' if r['ok'] else 'NO'} |")
        else:
            print(f"{inj:<60} seed {seed}: found {', '.join(r['found']) or 'none':<40} E {r['baseline']:.3f} -> "
                  f"{r['first_after']:.3f} (ratio {ratio:.2f}) -> {r['final']:.3f}  {'ok' if r['ok'] else 'FAIL'}  "
                  f"[{time.time() - t:.1f} s]")
        sys.stdout.flush()
    return 0 if ok_all else 1


if __name__ == "__main__":
    sys.exit(main())
