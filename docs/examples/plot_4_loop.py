"""
Closing the loop with a record
==============================

``drillpy loop`` starts from a declared model (here the rig as declared: hysteretic law, one
damping ratio), calibrates what the declaration leaves uncertain on the first half of a record,
and asks what is missing: each effect of the catalogue is calibrated in turn and must beat a
*null candidate* (the model recalibrated without it) on the held-out second half, by the
short-horizon prediction error E (every 0.25 s horizon restarted from the state the record
shows), a paired test, the BIC and the long run's stick-slip.

The record is synthetic: the rig with a top drive that is not the ideal one the declared model
assumes (``top_drive_dynamics``: a motor whose speed droops under the string's torque). To keep
the example short the search is limited to three candidates and one step (the command's default
searches the whole catalogue for up to six steps); docs/loop.md has the validation tables.
"""
import matplotlib.pyplot as plt
import numpy as np

import drillpy
from drillpy.loop.synthetic import declared_config

rec = drillpy.synthetic_record({"top_drive_dynamics": {}}, duration_s=24.0, seed=13, fs_hz=250.0)
options = drillpy.LoopOptions(rate_hz=250.0, effects=("top_drive_dynamics", "sensor_lag", "wob_coupling"),
                              max_steps=1, discovery=False)
res = drillpy.run_loop(rec, declared_config(), options, log=print)

# %%
# The steps: what was added, and the validation error before and after.
for s in res.steps:
    print(f"{s.action} {s.effect}: E {s.error_before:.3f} -> {s.error_after:.3f}")
print("fitted:", res.final.model.effects)

# %%
# Held-out horizons: the record's bit speed, the calibrated declared model's predictions and the
# corrected model's, each horizon restarted from the record's state at its start.
data = res.data
test = np.flatnonzero(data.is_test)[:6]
fig, ax = plt.subplots(figsize=(9, 3.8), layout="constrained")
for k, h in enumerate(test):
    idx = data.horizon_samples[h]
    ax.plot(data.t[idx], data.v_meas[idx], "k", lw=1.2, label="record" if k == 0 else None)
    ax.plot(data.t[idx], res.baseline.v[h], "C1", lw=0.9, label="declared model" if k == 0 else None)
    ax.plot(data.t[idx], res.final.v[h], "C0", lw=0.9, label="corrected model" if k == 0 else None)
ax.set(xlabel="time [s]", ylabel="bit speed [rad/s]", title=f"E {res.baseline.E_test:.3f} -> {res.final.E_test:.3f}")
ax.legend()
plt.show()
