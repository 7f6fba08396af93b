"""A record with an artifact of every kind, predicted by a rig model: what the cleaning keeps out (issue 28, item 4).

    PYTHONPATH=python python3 -m drillpy analyze ../shared/data/testrig/sample175_0-40s.mat --calibrate 0:20 --out DIR
    PYTHONPATH=python python3 benchmarks/artifact_record.py --model DIR/model.json [--out OUT.mat]

Takes the 20-40 s half of sample 175, shifts its time to start at 40 s (as a later part of a record
would), and puts into it, with a fixed seed:

* a top-speed artifact stretch while the bit slips (44-45.5 s: the encoder jumping between about
  -200 and +50 RPM), 30 isolated top-speed spikes to -200 RPM, 10 bit-speed spikes to 900 RPM and
  10 torque spikes to -40 N m;
* 0.3 s of NaN WOB (50 s), the torque dropped out to 0 N m for 0.2 s (52 s), the bit encoder frozen
  for 0.4 s (55 s) and the WOB load cell saturated at 2000 N for 0.5 s (57 s): held values.

It writes the record in the rig's MATLAB layout (``--out``) and prints, for the model of ``--model``
(``drillpy predict``'s :func:`drillpy.loop.prediction.predict_record`): the short-horizon error E, the
WOB's and top speed's standard deviations and SS on the clean half (20-40 s of the original) and on the
record with the artifacts, and the artifacts the cleaning reported. (Before the held values were
flagged, at commit c89a716, ``drillpy predict DIR/model.json OUT.mat --json`` gave E 1.094 and a WOB
standard deviation of 274 N on this record: the saturated WOB passed as data.)
"""
from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import numpy as np
import scipy.io as sio

from drillpy.loop.prediction import load_model, predict_record
from drillpy.records.cleaning import clean
from drillpy.records.io import read_record

RECORD = Path(__file__).resolve().parents[1] / ".." / "shared" / "data" / "testrig" / "sample175_0-40s.mat"
NAMES = ("Time", "Bit_Speed", "Top_Speed", "Bit_Torque", "WOB")


def artifact_record(source: Path, out: Path, seed: int = 3) -> None:
    """Write the 20-40 s half of ``source``, shifted to 40-60 s, with the artifacts of the module's docstring."""
    m = sio.loadmat(str(source))
    ch = {n: m[n + "_Sample_175_complete"].ravel() for n in NAMES}
    keep = ch["Time"] >= 20.0
    ch = {n: v[keep].copy() for n, v in ch.items()}
    ch["Time"] = ch["Time"] + 20.0
    t = ch["Time"]
    rng = np.random.default_rng(seed)

    def span(a, b):
        return (t >= a) & (t < b)

    s = span(44.0, 45.5)
    ch["Top_Speed"][s] = np.where(rng.random(s.sum()) < 0.5, -200.0, 50.0) + rng.normal(0.0, 5.0, s.sum())
    for name, count, value in (("Top_Speed", 30, -200.0), ("Bit_Speed", 10, 900.0), ("Bit_Torque", 10, -40.0)):
        ch[name][rng.choice(t.size, count, replace=False)] = value
    ch["WOB"][span(50.0, 50.3)] = np.nan
    ch["Bit_Torque"][span(52.0, 52.2)] = 0.0
    s = span(55.0, 55.4)
    ch["Bit_Speed"][s] = ch["Bit_Speed"][s][0]
    ch["WOB"][span(57.0, 57.5)] = 2000.0
    sio.savemat(str(out), {n + "_Sample_175_complete": v[:, None] for n, v in ch.items()})


def _row(label: str, pred) -> str:
    lr = pred.summary()["long_run"]
    return (f"| {label} | {pred.summary()['short_horizon_error']:.3f} | {lr['wob_std_n']['measured']:.1f} | "
            f"{lr['top_speed_std_rad_s']['measured']:.3f} | {lr['ss']['measured']:.3f} | "
            f"{lr['ss']['predicted']:.3f} | {lr['stalls']['measured']['count']} |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--model", required=True, help="model.json of drillpy analyze --calibrate")
    ap.add_argument("--out", help="where to write the record (default: a temporary file)")
    ap.add_argument("--record", default=str(RECORD), help="sample 175 (0-40 s)")
    a = ap.parse_args()
    model = load_model(a.model)
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(a.out) if a.out else Path(tmp) / "artifacts.mat"
        artifact_record(Path(a.record), out)
        _, rep = clean(read_record(out))
        print("artifacts found (kind, channel, start-end [s], samples, excluded):")
        for art in rep.artifacts:
            if art.kind != "spike":
                print(f"  {art.kind}, {art.channel}, {art.start_s:.3f}-{art.end_s:.3f}, {art.samples}, "
                      f"{'no' if art.repaired else 'yes'}")
        c = rep.counts()["spike"]
        print(f"  and {c['events']} isolated spikes ({c['repaired_samples']} samples repaired)")
        print("| record | E | WOB sd [N] | top-speed sd [rad/s] | SS measured | SS predicted | stalls |")
        print("|---|---|---|---|---|---|---|")
        print(_row("20-40 s of sample 175", predict_record(model, a.record, t0=20.0, t1=40.0)))
        print(_row("the same with the artifacts (40-60 s)", predict_record(model, out)))


if __name__ == "__main__":
    main()
