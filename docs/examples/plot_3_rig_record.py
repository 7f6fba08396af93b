"""
Analyzing a rig record
======================

A measured record goes through three steps: read (MATLAB files of the rig or the CSV format of the
README, converted to SI), clean (encoder spikes, gaps and non-finite values found, repaired where
the evidence allows and flagged), analyse (stick-slip cycles and their statistics, the bit-rock laws
of chapter 5 identified on the slip phases with their uncertainty, and the rig model calibrated on
the record). ``drillpy analyze RECORD --out DIR`` does all of it and writes a report; here the
library's pieces are called one by one.

The record is synthetic (:func:`drillpy.synthetic_record`: the test rig with measurement noise and
a fluctuating WOB), written to CSV with three encoder spikes and a short gap of the kind the real
records have; ``drillpy analyze ../shared/data/testrig/sample175_0-40s.mat`` runs the same analysis
on the thesis's sample 175.
"""
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import drillpy
from drillpy.records.analysis import AnalysisOptions, compute_analysis

rec = drillpy.synthetic_record(duration_s=30.0, seed=3)
rec.bit_speed[[3000, 7000, 11000]] += 40.0   # encoder spikes [rad/s]
rec.torque_on_bit[5000:5010] = np.nan        # a 20 ms hole in the torque channel
path = Path(tempfile.mkdtemp()) / "rig_run.csv"
drillpy.write_csv(rec, path)
print(path.read_text().splitlines()[1])  # the canonical header

# %%
# Reading and cleaning: every artifact is reported with its channel and time.
raw = drillpy.read_record(path)
cleaned, report = drillpy.clean(raw)
for a in report.artifacts:
    print(f"{a.kind:10s} {a.channel:14s} {a.start_s:7.3f}-{a.end_s:7.3f} s ({a.samples} samples)")

# %%
# The analysis: cycles, the laws identified on the slip phases, the rig model calibrated.
ana = compute_analysis(cleaned, AnalysisOptions(folds=0), log=lambda *args: None)
cs = ana.cycle_stats
print(f"{len(cs['period_s'])} cycles: period {np.mean(cs['period_s']):.3f} s, "
      f"stick {np.mean(cs['stick_s']):.3f} s, SS {np.nanmean(cs['ss']):.2f}")
for fit in ana.fits["constant_wob"]:
    print(f"{fit.name:22s} RMSE {fit.rmse:.3f} N m over {fit.n_clusters} cycles")

# %%
# The rig simulations: the preset as declared, then the identified law with each top drive, its
# damping calibrated on the record; one is kept as the calibrated model.
for label, (sim, comparison) in ana.simulations.items():
    print(f"{label}: mismatch {comparison.mismatch:.3f}, SS {comparison.simulated['ss']:.2f} "
          f"(record {comparison.measured['ss']:.2f})")

# %%
# The record's bit speed against the preset's and the calibrated model's, and the torque against
# the bit speed with the best-fitting law.
best = min(ana.fits["constant_wob"], key=lambda f: f.rmse)
preset = next(sim for label, (sim, _) in ana.simulations.items() if label.startswith("preset"))
calibrated = next(sim for label, (sim, _) in ana.simulations.items() if label.endswith("(calibrated model)"))
fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 3.8), layout="constrained")
r = ana.record
a1.plot(r.time_s, r.bit_speed, "k", lw=0.9, label="record")
a1.plot(preset.time_s, preset.bit_speed, lw=0.6, label="preset as declared")
a1.plot(calibrated.time_s, calibrated.bit_speed, lw=0.6, label="calibrated rig model")
a1.set(xlim=(r.time_s[0], r.time_s[0] + 5.0), xlabel="time [s]", ylabel="bit speed [rad/s]")
a1.legend()
slip = ana.branch != 0
a2.plot(r.bit_speed[slip], r.torque_on_bit[slip], ",", alpha=0.3, label="slip samples")
v = np.linspace(0.1, np.nanmax(r.bit_speed), 200)
a2.plot(v, drillpy.law_torque(best.law, v), "k", label=f"{best.name} law")
a2.set(xlabel="bit speed [rad/s]", ylabel="torque on bit [N m]")
a2.legend()
plt.show()
