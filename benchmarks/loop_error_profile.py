"""Where in a horizon the loop's error lives: the normalized error of each channel by time since the
restart, from a ``drillpy loop`` output folder (issue 28: what the residual still holds).

    PYTHONPATH=python python3 -m drillpy loop ../shared/data/testrig/sample175_0-40s.mat \
        --preset thesis-rig --out results/loop175
    python3 benchmarks/loop_error_profile.py results/loop175 [--bin-ms 25]

Reads ``predictions.csv`` (the record and the baseline's and final model's predictions of every
horizon) and ``model.json`` (``metric_scale``: the spreads E divides by) and prints, per bin of time
since the restart, the RMS of (predicted - measured) / spread of the bit speed and of the torque on
bit over the validation horizons, for the baseline and the final model. A torque error already
large in the first bin is no dynamics the model misses: the restart reproduces the measured state,
so what shows at once is the torque's fluctuation about the law (the law residual). NumPy only; a
second.
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np


def profile(out: Path, bin_ms: float) -> None:
    names = (out / "predictions.csv").read_text().splitlines()[1].split(",")
    d = np.genfromtxt(out / "predictions.csv", delimiter=",", skip_header=2)
    col = {n: d[:, i] for i, n in enumerate(names)}
    scale = json.loads((out / "model.json").read_text()).get("metric_scale")
    if scale is None:
        raise SystemExit(f"{out}/model.json has no metric_scale: rerun drillpy loop")
    sv, sT = scale["bit_speed_rad_s"], scale["torque_on_bit_nm"]
    t, hz = col["time_s"], col["horizon"]
    val = np.nan_to_num(col["validation"]) > 0
    print(f"{out}: validation horizons, spreads sd_v {sv:.3f} rad/s, sd_T {sT:.3f} N m")
    print(f"{'since restart [ms]':>20s} {'baseline v':>11s} {'baseline T':>11s} {'final v':>8s} {'final T':>8s}")
    rows = {}
    for h in np.unique(hz[np.isfinite(hz) & val]):
        idx = np.flatnonzero((hz == h) & val)
        k = np.floor((t[idx] - t[idx[0]]) * 1e3 / bin_ms).astype(int)
        for which in ("baseline", "final"):
            ev = (col[f"{which}_bit_speed_rad_s"][idx] - col["bit_speed_rad_s"][idx]) / sv
            eT = (col[f"{which}_torque_on_bit_Nm"][idx] - col["torque_on_bit_Nm"][idx]) / sT
            for b in np.unique(k):
                r = rows.setdefault(int(b), {})
                r.setdefault(which + "v", []).extend(ev[k == b] ** 2)
                r.setdefault(which + "T", []).extend(eT[k == b] ** 2)
    for b in sorted(rows):
        r = {key: float(np.sqrt(np.mean(x))) for key, x in rows[b].items()}
        print(f"{f'{b * bin_ms:g}-{(b + 1) * bin_ms:g}':>20s} {r['baselinev']:11.3f} {r['baselineT']:11.3f} "
              f"{r['finalv']:8.3f} {r['finalT']:8.3f}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", help="a drillpy loop output folder")
    ap.add_argument("--bin-ms", type=float, default=25.0)
    a = ap.parse_args()
    profile(Path(a.out), a.bin_ms)


if __name__ == "__main__":
    main()
