"""
Monte Carlo with the stochastic bit-rock law
============================================

Rock is not uniform: the torque on bit is T_law (1 + eta(t)) (Eq. 4.1), eta a Gaussian process with
the power spectral density of Eq. (4.4) fitted to the test rig. Above which top speed is the
probability of stick-slip below 5 %? Every sample runs every speed with the same realization of
eta (common random numbers), so the curves are smooth in the speed even with few samples. Sample
i depends only on (seed, i): the same numbers on any thread count.

A coarse model and 64 samples keep this example short; ``drillpy mc --preset thesis-field
--samples 500`` is the full study (P(SS > 0.5) <= 5 % above 19.95 rad/s there).
"""
import matplotlib.pyplot as plt
import numpy as np

import drillpy

cfg = drillpy.with_overrides(drillpy.load_config(preset="thesis-field"), elements=20, modes=5)

# %%
# A realization of eta and its periodogram against the model's PSD.
eta_dt = 0.05  # [s], the Monte Carlo's step
t, eta = drillpy.generate(drillpy.THESIS_PSD, dt=eta_dt, duration=2000.0, seed=1)
f, s = drillpy.periodogram(eta[0], eta_dt)
print(f"std of eta: {eta[0].std():.4f} (model {np.sqrt(drillpy.THESIS_PSD.integral()):.4f})")

fig, ax = plt.subplots(figsize=(7, 3.2), layout="constrained")
ax.loglog(f[1:], s[1:], lw=0.5, label="periodogram of one realization")
ax.loglog(f[1:], drillpy.THESIS_PSD(f[1:]), "k", label="Eq. (4.4)")
ax.set(xlabel="frequency [Hz]", ylabel="PSD [1/Hz]")
ax.legend()

# %%
# The study: SS of every sample at every speed, its mean and 90 % band, and P(SS > 0.5).
speeds = np.arange(18.0, 28.0, 1.0)
study = drillpy.stochastic_study(cfg, speeds, samples=64, seed=1, progress=False)
for v, m, p in zip(speeds, study.mean, study.p_exceed):
    print(f"{v:5.1f} rad/s: mean SS {m:5.2f}, P(SS > 0.5) = {p:.2f}")
print(f"P(SS > 0.5) <= 5 % from {study.p05_speed} rad/s; deterministic threshold {study.deterministic_threshold:.2f} rad/s")

fig, (a1, a2) = plt.subplots(1, 2, figsize=(9, 3.4), layout="constrained")
a1.fill_between(speeds, study.q05, study.q95, alpha=0.3, label="5-95 %")
a1.plot(speeds, study.mean, "o-", label="mean")
a1.plot(speeds, study.deterministic, "k--", label="deterministic")
a1.set(xlabel="top speed [rad/s]", ylabel="SS [-]")
a1.legend()
a2.plot(speeds, study.p_exceed, "o-")
a2.axhline(0.05, color="k", lw=0.8)
a2.set(xlabel="top speed [rad/s]", ylabel="P(SS > 0.5)")
plt.show()
