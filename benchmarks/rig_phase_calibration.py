"""The whole-rig calibration asked to match the drive's phase as well (issue 28): ``calibrate_rig`` with
``top_in_phase`` (the top speed's part in phase with the bit speed at the cycle frequency,
``rig_comparison.record_metrics``) added to its metrics, beside the model of ``drillpy analyze``.

    PYTHONPATH=python python3 benchmarks/rig_phase_calibration.py DIR/model.json [--t0 0 --t1 20]

DIR from ``drillpy analyze ../shared/data/testrig/sample175_0-40s.mat --calibrate 0:20 --out DIR`` (its
law, the one identified on the window, is kept). Prints the calibrated parameters, then every metric
measured / with analyze's model / with the calibration that matches the phase too, and the mismatch of
each over the default metrics and over the default metrics with the phase. The default calibration
matches the size of the top's swing but not its phase (``benchmarks/rig_phases.py``); if a model of
the rig family had both, this calibration would find it. About 7 minutes on 2 cores.
"""
from __future__ import annotations

import argparse
from pathlib import Path

from drillpy.loop.prediction import load_model
from drillpy.records import rig_calibration, rig_comparison, rigsim
from drillpy.records.cleaning import clean
from drillpy.records.io import read_record

SAMPLE175 = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"
KEYS = rigsim.MATCHED_RIG + ("top_in_phase",)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("model")
    ap.add_argument("--record", default=str(SAMPLE175))
    ap.add_argument("--t0", type=float, default=0.0)
    ap.add_argument("--t1", type=float, default=20.0)
    a = ap.parse_args()
    m0 = load_model(a.model)
    rec, _ = clean(read_record(a.record).select(a.t0, a.t1))
    thr = rigsim.stick_threshold(rec)
    cal = rig_calibration.calibrate_rig(rec, m0.law, thr, keys=KEYS, log=print)
    models = {"analyze": m0, "with phase": cal.model}
    cmp = {k: rig_comparison.compare(rec, rigsim.simulate_model(m, rec), thr, keys=KEYS) for k, m in models.items()}
    print(f"{'metric':>18} {'measured':>9} " + " ".join(f"{k:>10}" for k in models))
    for key in KEYS:
        print(f"{key:>18} {cmp['analyze'].measured[key]:9.3f} " + " ".join(f"{c.simulated[key]:10.3f}" for c in cmp.values()))
    for label, keys in (("mismatch, default metrics", rigsim.MATCHED_RIG), ("mismatch, with the phase", KEYS)):
        print(f"{label:>28}: " + ", ".join(f"{k} {rig_comparison.compare(rec, rigsim.simulate_model(m, rec), thr, keys=keys).mismatch:.3f}"
                                          for k, m in models.items()))


if __name__ == "__main__":
    main()
