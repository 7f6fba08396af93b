"""``drillpy loop`` on the test-rig record, sample 175 (0-40 s): its wall time and its answer, with
the horizons stepped by the scalar reference integrator (the default) and by the batched SIMD one
(``LoopOptions.batched``), measured in one run (issue 16; docs/loop.md).

    PYTHONPATH=python python3 benchmarks/loop_sample175.py [--batched-only] [--rate 250]

Prints per path: wall time, the steps (action, effect, E before -> after, the corrected model's
long run: SS / stick fraction / cycle frequency) and the record's long run, then the ratio of the
wall times. The machine is shared: read the ratio.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "python"))
SAMPLE175 = REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"


def _lr(m: dict) -> str:
    return f"{m['ss']:.3f} / {m['stick_fraction']:.3f} / {m['cycle_frequency_hz']:.2f} Hz"


def run(batched: bool, rate: float, record: str) -> float:
    """Run the loop on one path and print its answer; returns the wall time [s]."""
    import drillpy
    from drillpy.loop import LoopOptions, run_loop
    cfg = drillpy.load_config(preset="thesis-rig")
    t0 = time.perf_counter()
    res = run_loop(record, cfg, LoopOptions(rate_hz=rate, batched=batched), log=lambda *a: None)
    wall = time.perf_counter() - t0
    print(f"{'batched SIMD' if batched else 'scalar (reference)'}: {wall:.1f} s; baseline E {res.baseline.E_test:.3f}")
    for s in res.steps:
        lr = s["long_run"]
        print(f"  {s['action']:<6} {s['effect']:<20} E {s['error_before']:.3f} -> {s['error_after']:.3f}   "
              f"long run {_lr(lr['after'])}" if lr else "")
    if res.steps:
        print(f"  record's long run {_lr(res.steps[-1]['long_run']['measured'])}")
    sys.stdout.flush()
    return wall


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--batched-only", action="store_true", help="run the batched path only")
    ap.add_argument("--rate", type=float, default=250.0, help="analysis rate [Hz] (docs/loop.md: 250)")
    ap.add_argument("--record", default=str(SAMPLE175))
    a = ap.parse_args()
    batched = run(True, a.rate, a.record)
    if not a.batched_only:
        scalar = run(False, a.rate, a.record)
        print(f"wall time scalar / batched: {scalar / batched:.2f} x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
