"""
A string's stick-slip threshold
===============================

At which top-drive speed does a string stop stick-slipping? Take the thesis's field string
(Table 3.1), sweep the stick-slip severity SS (Eq. 3.4) over the top speed and read the speed below
which SS > 0.5, first on the grid, then by bisection. A coarse mesh (20 elements, 5 modes) keeps
the example fast; the full model (``preset="thesis-field"`` as it is) gives 19.7 rad/s on the grid.
"""
import matplotlib.pyplot as plt
import numpy as np

import drillpy

cfg = drillpy.load_config(preset="thesis-field")
cfg = drillpy.with_overrides(cfg, elements=20, modes=5)
print(drillpy.natural_frequencies(cfg, 3))  # [Hz], the first three modes of the coarse model

# %%
# One run below the threshold: the bit sticks and slips.
run = drillpy.simulate(cfg, top_speed=12.0)
print(f"SS = {run.severity:.2f}, {len(run.stick_durations)} stick phases after the transient")

fig, ax = plt.subplots(figsize=(7, 3.2), layout="constrained")
ax.plot(run.t, run.bit_speed, lw=0.8, label="bit")
ax.axhline(12.0, color="k", ls="--", lw=0.8, label="top (imposed)")
ax.set(xlabel="time [s]", ylabel="speed [rad/s]", title="stick-slip at 12 rad/s")
ax.legend()

# %%
# The sweep runs every speed in parallel; the threshold is interpolated on the grid.
speeds = np.arange(6.0, 28.0, 2.0)
ss = drillpy.sweep_severity(cfg, speeds, progress=False)
threshold = drillpy.severity_threshold(speeds, ss)
print(f"SS > 0.5 below {threshold:.2f} rad/s")

fig, ax = plt.subplots(figsize=(7, 3.2), layout="constrained")
ax.plot(speeds, ss, "o-")
ax.axhline(0.5, color="k", lw=0.8)
ax.axvline(threshold, color="r", ls="--", lw=0.8)
ax.set(xlabel="top speed [rad/s]", ylabel="SS [-]", title=f"threshold {threshold:.2f} rad/s")
plt.show()
