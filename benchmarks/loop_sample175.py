"""``drillpy loop`` on the test-rig record, sample 175 (0-40 s): its wall time and its answer, before
and after the loop's speed work of issue 16, measured in one run (docs/loop.md).

    PYTHONPATH=python python3 benchmarks/loop_sample175.py [--rate 250] [--only after]

Three configurations of :class:`drillpy.loop.LoopOptions`, run one after the other:

* ``before``: the horizons stepped by the scalar reference integrator, the BLAS library's default
  thread count (the loop as it ran before: ``batched=False, blas_threads=0``);
* ``scalar``: the scalar integrator, the optimizer's linear algebra on one BLAS thread;
* ``after``: the defaults (the batched SIMD integrator, one BLAS thread).

Prints per configuration: wall time, the steps (action, effect, E before -> after, the corrected
model's long run: SS / stick fraction / cycle frequency), the record's long run, then the ratios of
the wall times. The machine is shared: read the ratios.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))
SAMPLE175 = REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"
CONFIGS = {"before": {"batched": False, "blas_threads": 0}, "scalar": {"batched": False}, "after": {}}


def _lr(m: dict) -> str:
    return f"{m['ss']:.3f} / {m['stick_fraction']:.3f} / {m['cycle_frequency_hz']:.2f} Hz"


def run(name: str, rate: float, record: str) -> float:
    """Run the loop in configuration ``name`` and print its answer; returns the wall time [s]."""
    import drillpy
    from drillpy.loop import LoopOptions, run_loop
    cfg = drillpy.load_config(preset="thesis-rig")
    t0 = time.perf_counter()
    res = run_loop(record, cfg, LoopOptions(rate_hz=rate, **CONFIGS[name]), log=lambda *a: None)
    wall = time.perf_counter() - t0
    print(f"{name} {CONFIGS[name] or '(defaults)'}: {wall:.1f} s; baseline E {res.baseline.E_test:.3f}")
    for s in res.steps:
        lr = s.long_run
        print(f"  {s.action:<6} {s.effect:<20} E {s.error_before:.3f} -> {s.error_after:.3f}   "
              + (f"long run {_lr(lr['after'])}" if lr else ""))
    if res.steps:
        print(f"  record's long run {_lr(res.steps[-1].long_run['measured'])}")
    sys.stdout.flush()
    return wall


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--only", choices=tuple(CONFIGS), help="run one configuration only")
    ap.add_argument("--rate", type=float, default=250.0, help="analysis rate [Hz] (docs/loop.md: 250)")
    ap.add_argument("--record", default=str(SAMPLE175))
    a = ap.parse_args()
    names = (a.only,) if a.only else tuple(CONFIGS)
    wall = {n: run(n, a.rate, a.record) for n in names}
    if len(wall) == len(CONFIGS):
        print(f"wall time before / after: {wall['before'] / wall['after']:.2f} x; scalar / after (the batched "
              f"integrator alone): {wall['scalar'] / wall['after']:.2f} x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
