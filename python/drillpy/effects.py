"""The catalogue of candidate effects of ``drillpy loop``: model extensions a declared model may lack.

Each effect is a real change of the model with its own parameters, a diagnostic signature in the
residual, and a physical reading on the test rig. The loop (:mod:`drillpy.loop`) fits each missing
effect on the calibration part of a record and keeps the one the evidence supports.

======================= ======= =============================================================================
effect                  level   model change (parameters)
======================= ======= =============================================================================
``bit_hysteresis``      law     T = T_law(v) (1 + H), H = beta1 tanh(beta2 a) sign(v)  (Eqs. 3.2-3.3, 5.3)
                                (beta1 [-], beta2 [s/speed unit])
``wob_coupling``        law     the law at the measured WOB: T = T_law(v, a) W_eff / W_0,
                                W_eff = W_0 (1 + k (W(t) / W_0 - 1))   (k [-]; k = 1: T proportional to W)
``top_drive_dynamics``  dynamic the top speed is not the constant the model assumed: an open-loop motor,
                                J_m Omega' = c_m (Omega_c - Omega) - T_top  (droop 1/c_m [rad/s per N m],
                                J_m [kg m^2], command Omega_c [rad/s]; drill/topdrive.hpp), started at the
                                measured top speed; or (variant ``measured``) the top driven by the measured
                                top speed
``sensor_lag``          dynamic the recorded channels went through a second-order Butterworth low-pass at f_c
                                [Hz] (drill/sensor.hpp): the model's outputs pass through it, its state comes
                                from the recorded values and rates, the model's state from the channels with
                                the filter undone, x = y + (sqrt(2)/omega_c) y' + y''/omega_c^2
``torque_fluctuation``  dynamic T = T_law (1 + eta(t)) (Eq. 4.1) with eta coloured: white noise through a
                                critically damped second-order low-pass of time constant tau [s] (PSD falling
                                as f^-4, the steep shape of Eq. 4.4). Its state (eta, eta') at a restart is
                                estimated from the record's past (a line fitted to T/T_law - 1 over the slip
                                samples with weights exp(-age/m), memory m [s]) and the prediction uses the
                                conditional mean exp(-s/tau) [eta (1 + s/tau) + s eta'] over the horizon
``viscous_damping``     dynamic an extra viscous torque c_v v [N m s/rad] on the bit that the torque sensor
                                (under the rock holder) does not see
======================= ======= =============================================================================

Law-level parameters are fitted by least squares on the law residual together with the law's own
parameters; dynamic parameters by least squares on the short-horizon prediction error
(:mod:`drillpy.loop`).
"""
from __future__ import annotations

from dataclasses import dataclass

NAMES = ("bit_hysteresis", "wob_coupling", "top_drive_dynamics", "sensor_lag", "torque_fluctuation",
         "viscous_damping")


@dataclass(frozen=True)
class Effect:
    """One entry of the catalogue (descriptions used by the report and the documentation)."""
    name: str
    level: str         #: "law" (fitted on the law residual) or "dynamic" (on the horizon predictions)
    parameters: tuple  #: ((name, unit, meaning), ...)
    change: str        #: the model change
    signature: str     #: what the effect leaves in the residual of a model without it
    reading: str       #: physical reading on the test rig (thesis chapter 5)
    needs: tuple = ()  #: record channels it needs besides bit speed and torque on bit


CATALOGUE = {
    "bit_hysteresis": Effect(
        "bit_hysteresis", "law",
        (("beta1", "-", "amplitude of H (Eq. 3.3)"), ("beta2", "s/speed unit", "acceleration scale of H")),
        "T = T_law(v) (1 + beta1 tanh(beta2 a) sign(v)) (Eqs. 3.2-3.3; 5.3 for the polynomial law)",
        "a law residual of the sign of the bit acceleration, proportional to the speed-dependent part of "
        "the torque: torque above the law while the bit accelerates, below while it decelerates (the "
        "upper and lower branches of Fig. 3.5)",
        "the bit-rock torque depends on where the bit is in the cycle, not only on its speed: the "
        "accelerating and decelerating branches of the rig's torque-speed loop (Figs. 3.5, 5.7)"),
    "wob_coupling": Effect(
        "wob_coupling", "law", (("gain", "-", "k: relative torque change per relative WOB change"),),
        "T = T_law(v, a) (1 + k (W(t)/W_0 - 1)), the measured WOB W(t) as an input",
        "a law residual proportional to T_law (W(t) - W_0) / W_0",
        "axial-torsional coupling: the WOB oscillates with the stick-slip cycle (section 5.3.2) and slowly "
        "with the electrical jack's on-off control, and the cutting torque follows it",
        needs=("wob",)),
    "top_drive_dynamics": Effect(
        "top_drive_dynamics", "dynamic",
        (("droop_rad_s_per_nm", "rad/s per N m", "1/c_m: speed lost per N m of top torque"),
         ("inertia_kg_m2", "kg m^2", "J_m: motor and drive-train inertia"),
         ("command_rad_s", "rad/s", "Omega_c: no-load (commanded) speed")),
        "J_m Omega' = c_m (Omega_c - Omega) - T_top (drill/topdrive.hpp), started at the measured top "
        "speed; variant `measured`: the top follows the measured top speed",
        "a bit-speed residual that follows the top speed's departure from the constant the model "
        "assumed (the string is wound up or unwound from above)",
        "the rig's open-loop DC motor gives way under load: its speed drops 40-60 % and oscillates with "
        "the stick-slip cycle (section 5.3.2); it stalls when the bit sticks at a torque it cannot "
        "overcome",
        needs=("top_speed",)),
    "sensor_lag": Effect(
        "sensor_lag", "dynamic", (("lowpass_hz", "Hz", "cutoff f_c of a second-order Butterworth low-pass"),),
        "the model's outputs through y'' + sqrt(2) omega_c y' + omega_c^2 y = omega_c^2 x (drill/sensor.hpp), "
        "its state from the channels with the filter undone",
        "residuals early in every horizon, where the recorded channels lag and round off what the model "
        "predicts from a state read off lagged channels (sharpest at the stick-slip transitions)",
        "the acquisition's second-order IIR low-pass at 10 Hz on every channel, encoders included "
        "(section 5.3.1), put there against the platform's 20 Hz mode"),
    "torque_fluctuation": Effect(
        "torque_fluctuation", "dynamic",
        (("tau_s", "s", "correlation time of eta"), ("memory_s", "s", "memory of the estimate of eta from the past"),
         ("std", "-", "standard deviation of eta (estimated, reported)")),
        "T = T_law (1 + eta(t)) (Eq. 4.1), eta white noise through a critically damped second-order low-pass "
        "(time constant tau): at a restart (eta, eta') from the past of T/T_law - 1, then the conditional mean "
        "exp(-s/tau) [eta (1 + s/tau) + s eta'] over the horizon",
        "a law residual, relative to T_law, that its own recent past predicts (correlated over longer than "
        "the horizon)",
        "slow changes of the bit-rock contact that no input explains: rock heterogeneity, cuttings, wear, "
        "the lateral friction of the bit in its hole (section 5.3.2); the fluctuation process of chapter 4"),
    "viscous_damping": Effect(
        "viscous_damping", "dynamic", (("bit_viscous_nms", "N m s/rad", "c_v: viscous torque per unit bit speed"),),
        "an extra torque c_v v on the bit, outside the torque sensor (operation.bit_viscous_nms)",
        "a bit-speed residual growing with the bit speed over the horizon: the bit decelerates more than "
        "the measured torque explains",
        "drag of the water added while drilling (section 5.3.1, step 5) on the disk and bit, and the "
        "lower bearing"),
}


def declared_effects(cfg: dict) -> dict:
    """The catalogue's effects a declared configuration already has, with their parameters."""
    out = {}
    law = cfg["law"]
    if float(law.get("beta1", 0.0)) > 0.0:
        out["bit_hysteresis"] = {"beta1": float(law["beta1"]), "beta2": float(law["beta2"])}
    td = cfg.get("top_drive", {"type": "ideal"})
    if td.get("type") == "motor":
        out["top_drive_dynamics"] = {"variant": "motor", "droop_rad_s_per_nm": 1.0 / float(td["slope_nms_rad"]),
                                     "inertia_kg_m2": float(td["inertia_kg_m2"]),
                                     "command_rad_s": float(cfg["operation"]["top_speed_rad_s"])}
    fc = float(cfg.get("sensors", {}).get("lowpass_hz", 0.0))
    if fc > 0.0:
        out["sensor_lag"] = {"lowpass_hz": fc}
    cv = float(cfg["operation"].get("bit_viscous_nms", 0.0))
    if cv > 0.0:
        out["viscous_damping"] = {"bit_viscous_nms": cv}
    return out
