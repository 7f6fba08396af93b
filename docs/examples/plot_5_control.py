"""
Controlling stick-slip with the top drive
=========================================

The thesis turns the top of the string at a prescribed speed. A real top drive has an inertia and
a speed controller, and the controller can fight stick-slip: ``soft_speed`` tunes a PI to the drill
pipe's impedance (the SoftSpeed principle), ``z_torque`` feeds the measured top torque back as an
impedance (the ZTorque principle), ``stiff`` holds the speed like the ideal drive. docs/control.md
has the equations, the tuning rules and the measured tables; ``drillpy control`` tunes the gains
robustly under the random bit-rock law.

Here the field string (coarse mesh) is driven at 12 rad/s, deep in stick-slip with the ideal drive,
by a 2000 kg m^2 drive with each controller.
"""
import matplotlib.pyplot as plt

import drillpy

base = drillpy.with_overrides(drillpy.load_config(preset="thesis-field"), elements=20, modes=5)
drives = {"ideal": None}
for kind in ("stiff", "soft_speed", "z_torque"):
    drives[kind] = {"type": "controlled", "inertia_kg_m2": 2000.0,
                    "controller": {"type": kind, "torque_limit_nm": 50000.0}}

runs = {}
for name, drive in drives.items():
    cfg = base if drive is None else drillpy.with_overrides(base, top_drive=drive)
    runs[name] = drillpy.simulate(cfg, top_speed=12.0)
    print(f"{name:10s} SS {runs[name].severity:5.2f}, stick fraction {runs[name].stick_fraction:.2f}")

# %%
# Bit speed and the motor's torque with each drive.
fig, (a1, a2) = plt.subplots(2, 1, figsize=(8, 5), sharex=True, layout="constrained")
for name, run in runs.items():
    a1.plot(run.t, run.bit_speed, lw=0.7, label=name)
    a2.plot(run.t, run.top_torque / 1e3, lw=0.7, label=name)
a1.set(ylabel="bit speed [rad/s]")
a2.set(xlabel="time [s]", ylabel="top torque [kN m]")
a1.legend(ncol=4)
plt.show()
