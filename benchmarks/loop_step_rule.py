"""The loop's step rule (``drillpy.loop.time_step``, issue 33) on records of several kinds: the
differences d it measures at each step it tries, the step it takes and the calibrated baseline's d.

    PYTHONPATH=python python3 benchmarks/loop_step_rule.py [--tolerance 0.0035]

Records, each from ``thesis-rig`` (its own step 1e-4 s): the test rig's sample 175 (0-40 s, 1000 Hz),
the second outside simulator's clean record (``benchmarks/stribeck_rig.py``, seed 1, 250 Hz) and four
truths of ``drillpy.loop.synthetic.synthetic_record`` (40 s, 500 Hz: no effect, the motor, static
friction, the WOB coupling), each with the loop's defaults and no effect search (``max_steps=0``).
About a minute.
"""
from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "benchmarks"))
if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))
SAMPLE175 = REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"


def records(folder: str) -> list:
    """(name, record or path, rate [Hz], declared configuration)."""
    import drillpy
    import stribeck_rig
    from drillpy.loop.synthetic import declared_config, synthetic_record
    preset = drillpy.load_config(preset="thesis-rig")
    path = os.path.join(folder, "stribeck_clean_1.csv")
    stribeck_rig.make_record("clean", 1, path)
    out = [("sample 175", str(SAMPLE175), 1000.0, preset), ("Stribeck rig, clean, seed 1", path, 250.0, preset)]
    for effects, seed in (((), 1), ({"top_drive_dynamics": {}}, 4), ({"static_friction": {}}, 5),
                          ({"wob_coupling": {}}, 6)):
        name = "synthetic_record " + (", ".join(effects) or "no effect") + f", seed {seed}"
        out.append((name, synthetic_record(effects, duration_s=40.0, seed=seed, fs_hz=500.0), 500.0,
                    declared_config()))
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tolerance", type=float, default=None, help="the rule's tolerance (default: the loop's)")
    a = ap.parse_args()
    from drillpy.loop import LoopOptions, run_loop
    extra = {} if a.tolerance is None else {"step_tolerance": a.tolerance}
    with tempfile.TemporaryDirectory() as folder:
        for name, rec, rate, cfg in records(folder):
            res = run_loop(rec, cfg, LoopOptions(rate_hz=rate, max_steps=0, long_run=False, discovery=False, **extra),
                           log=lambda *x: None)
            ts = res.time_step
            tried = ", ".join(f"{x['difference']:.4f} at {x['dt_s']:.3g} s" for x in ts["tried"])
            base = f"{ts['baseline_difference']:.4f}" if "baseline_difference" in ts else "n/a"
            print(f"{name}: declared {ts['declared_s']:.3g} s; d {tried}; tolerance {ts['tolerance']:g}; step taken "
                  f"{ts['used_s']:.3g} s; the calibrated baseline's d {base}; baseline validation E "
                  f"{res.baseline.E_test:.4f}")
            sys.stdout.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
