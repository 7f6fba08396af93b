"""``top_drive_dynamics``: the top does not turn at the constant speed the model assumed."""
from __future__ import annotations

import numpy as np

from drillpy.records.io import RPM
from drillpy.records.rigsim import RIG_PARAMETERS, add_coupling, remove_coupling

from .base import Effect, Param
from ..view import view

#: The coupling's range (the whole-rig model's, with its source: rigsim.RIG_PARAMETERS); at the upper
#: bound the coupling is rigid next to the rig's bar (3.08 N m/rad), which is no coupling.
COUPLING = RIG_PARAMETERS["coupling_stiffness_nm_rad"]

#: The motor inertia is bounded below by this multiple of the modified-Euler stability floor (Eq. A.7):
#: at the floor the coupled motor mode has 10 steps per period; at 4 x, about 20 (it is resolved).
RESOLVED = 4.0
#: The motor inertia's range [kg m^2] (its lower end also raised to the engine's resolution, :meth:`TopDriveDynamics.bounds`).
INERTIA_RANGE = (1e-6, 10.0)
#: A top speed whose standard deviation is below this fraction of its mean is steady: no drive model
#: can be credited with explaining it (the encoder's noise on the rig is about 0.6 % of 8.5 rad/s).
STEADY_TOP = 0.01


#: A motor whose time constant J_m / c_m is below this [s] has no inertia a record resolves: 1 ms is
#: the sample interval of a 1000 Hz record, the finest the loop analyses (sample 175's rate).
RESOLVED_TIME_S = 1e-3


def quasi_static(p: dict) -> bool:
    """True when the motor's time constant J_m / c_m is below :data:`RESOLVED_TIME_S` (1 ms): the
    record resolves no inertia, the motor acts as a speed droop Omega = Omega_c - T / c_m (through
    the coupling, a spring in series with the droop's damper), and J_m is no free parameter (not
    counted, flagged; the motor is then credited on its droop, command and coupling). Such a fit
    sits near the inertia's lower bound, which the engine's step sets (:meth:`TopDriveDynamics.bounds`).

    Parameters
    ----------
    p : dict
        The effect's values (``inertia_kg_m2`` J_m [kg m^2], ``droop_rad_s_per_nm`` 1/c_m).
    """
    j, droop = p.get("inertia_kg_m2"), p.get("droop_rad_s_per_nm")
    return p.get("variant", "motor") == "motor" and j is not None and droop is not None and \
        j * droop < RESOLVED_TIME_S


class TopDriveDynamics(Effect):
    """The top does not turn at the constant speed the ideal drive assumes: an open-loop motor
    J_m Omega' = c_m (Omega_c - Omega) - T_top (``drill/topdrive.hpp``), parameters
    ``droop_rad_s_per_nm`` 1/c_m [rad/s per N m], ``inertia_kg_m2`` J_m [kg m^2] (bounded below by the
    modified-Euler stability bound of Eq. A.7 at the engine step, times :data:`RESOLVED`) and
    ``command_rad_s`` Omega_c [rad/s] (``p["variant"]`` is ``"motor"``), the rotor turning the string
    through a shaft coupling of stiffness ``coupling_stiffness_nm_rad`` k_c [N m/rad] (a massless
    spring in series, :func:`drillpy.records.rigsim.add_coupling`; 2-300 N m/rad, the whole-rig
    model's range; at 300 it is rigid next to the rig's bar and only flagged). The candidate fits the
    four together: a motor without inertia fits the short horizons (the top speed follows the torque)
    but damps the cycle away, and the coupling lets the bar's top follow the torque while the rotor's
    inertia shields the mode. A motor declared without a coupling keeps three parameters.

    The kinematic variant ``"measured"`` (the top following its measured speed, no parameter) is not
    a candidate of the loop: the measured top speed of an open-loop motor carries the stick-slip
    cycle, so a model fed it is given the answer it should predict. It expresses ``drillpy
    analyze``'s diagnosis model (the measured-top-speed drive) for its short-horizon error.

    Needs a top-speed channel (the restarts' top speed); flagged when the recorded top speed is
    steady (:data:`STEADY_TOP`).
    """
    name = "top_drive_dynamics"
    params = (Param("droop_rad_s_per_nm", "rad/s per N m", "1/c_m: speed lost per N m of top torque", 1e-3, 1e3, "log"),
              Param("inertia_kg_m2", "kg m^2", "J_m: motor and drive-train inertia (lower bound: 4 x the inertia at "
                    "which the modified-Euler stability bound of Eq. A.7 meets the engine step)", *INERTIA_RANGE, "log",
                    binding=False),
              Param("command_rad_s", "rad/s", "Omega_c: no-load (commanded) speed", 0.0, float("inf")),
              Param("coupling_stiffness_nm_rad", "N m/rad", "k_c: shaft coupling between the rotor and the string",
                    COUPLING[0], COUPLING[1], "log", binding=False))
    change = "J_m Omega' = c_m (Omega_c - Omega) - T_top (drill/topdrive.hpp), started at the measured top speed"
    signature = ("a bit-speed residual that follows the top speed's departure from the constant the model assumed "
                 "(the string is wound up or unwound from above)")
    reading = ("the rig's open-loop DC motor gives way under load: its speed drops 40-60 % and oscillates with the "
               "stick-slip cycle (section 5.3.2); it stalls when the bit sticks at a torque it cannot overcome")
    needs = ("top_speed",)
    defaults = {"slope_nms_rad": 0.25, "inertia_kg_m2": 0.02}
    inject_last = True  # the motor's command is set from the truth's law and extra torques

    def feeds_cycle(self, p):
        """True for the kinematic variant ``"measured"`` (the recorded top speed, which carries the
        cycle, drives the top); see :meth:`Effect.feeds_cycle`.

        Parameters
        ----------
        p : dict
            The effect's values (``p["variant"]``).
        """
        return p.get("variant") == "measured"

    def free(self, p):
        """The motor's parameters (the coupling's when ``p`` has one); none for the kinematic
        variant; see :meth:`Effect.free`.

        Parameters
        ----------
        p : dict
            The effect's values (``p["variant"]``).
        """
        if p.get("variant") == "measured":
            return ()
        return tuple(q for q in self.params if q.name in p)

    def count(self, p):
        """4 for the motor behind a compliant coupling, 3 without one or behind a coupling fitted at
        its rigid bound (within 1 % of 300 N m/rad: the three-parameter motor, whose BIC it then
        has), one less for a quasi-static motor (:func:`quasi_static`: an inertia no record resolves
        carries no freedom), 0 for the kinematic variant; see :meth:`Effect.count`.

        Parameters
        ----------
        p : dict
            The effect's values (``p["variant"]``).
        """
        k = p.get("coupling_stiffness_nm_rad")
        rigid = k is not None and k >= 0.99 * COUPLING[1]
        return len(self.free(p)) - int(rigid) - int(quasi_static(p))

    def describe(self, p):
        """The motor's droop in RPM per N m, c_m, its inertia (or the quasi-static droop), no-load
        speed, stall torque and coupling; the kinematic variant's reading; see :meth:`Effect.describe`.

        Parameters
        ----------
        p : dict
            The effect's values.
        """
        if p.get("variant") == "measured":
            return "the top follows the measured top speed (kinematic drive: a diagnosis, fed the cycle it should predict)"
        c = 1.0 / p["droop_rad_s_per_nm"]
        inertia = (f"no inertia the record resolves (fitted at {p['inertia_kg_m2']:.3g} kg m^2, a time constant of "
                   f"{p['inertia_kg_m2'] / c:.2g} s: a quasi-static droop; a rotor's real inertia is not that small, so "
                   "the coupling or the drive train shields it)"
                   if quasi_static(p) else
                   f"inertia {p['inertia_kg_m2']:.3g} kg m^2 (time constant {p['inertia_kg_m2'] / c:.3g} s)")
        k = p.get("coupling_stiffness_nm_rad")
        return (f"the top drive gives way: a motor with droop {p['droop_rad_s_per_nm'] * RPM:.3g} RPM per N m "
                f"(c_m = {c:.3g} N m s/rad), {inertia}, no-load speed {p['command_rad_s'] * RPM:.1f} RPM, stall "
                f"torque {c * p['command_rad_s']:.2f} N m" + (f", behind a coupling of {k:.3g} N m/rad" if k else ""))

    def flags(self, p, data, model=None):
        """Flag a recorded top speed whose standard deviation is below :data:`STEADY_TOP` (1 %) of
        its mean over the valid, measured samples: the top already turns at the constant the model
        assumes; see :meth:`Effect.flags`.

        Parameters
        ----------
        p : dict
            The fitted values (not read).
        data : LoopData
            The record (its top-speed channel [rad/s] and ``top_ok`` mask).
        model : LoopModel, optional
            Not used.
        """
        ok = data.valid & data.top_ok
        top = data.ch["top"][ok]
        rel = float(np.std(top) / abs(np.mean(top))) if top.size else 0.0
        if rel < STEADY_TOP:
            return [f"the recorded top speed is steady (standard deviation {100 * rel:.2f} % of its mean, below "
                    f"{100 * STEADY_TOP:g} %): the top already turns at the constant the model assumes"]
        return []

    def bounds(self, q, model):
        """The motor inertia's lower bound raised to :data:`RESOLVED` times
        :func:`drillpy.loop.model.motor_inertia_floor` (Eq. A.7 at the engine step); the other
        parameters keep their own; see :meth:`Effect.bounds`.

        Parameters
        ----------
        q : Param
            One of the effect's parameters.
        model : LoopModel
            The model (its engine step and string).
        """
        if q.name == "inertia_kg_m2":  # the modified-Euler bound with the motor (Eq. A.7)
            from ..model import motor_inertia_floor
            return max(q.lower, RESOLVED * motor_inertia_floor(model)), q.upper
        return q.lower, q.upper

    def starts(self, model, data):
        """Motor starts: the motor equation J_m Omega' + c_m Omega - c_m Omega_c = -T_top is linear in
        (J_m, c_m, c_m Omega_c) given the top speed, its rate and the string's top torque of the states
        read off the record (least squares over the calibration part), plus a few droops, each
        behind a coupling of 30 N m/rad (the rotor's inertia then at least 0.02 kg m^2) and behind a
        nearly rigid one.

        The droop starts are 1 and 4 rad/s per N m and the quasi-static fit Omega = Omega_c -
        T_top / c_m, with motor time constants J_m / c_m of 0.01-0.05 s; every motor inertia is at
        least 1.5 x :data:`RESOLVED` x the stability floor. The string's top torque at the restart
        states is the engine's (``_core.top_torque_from_bit``) with the top at its measured speed and
        rate. See :meth:`Effect.starts`.

        Parameters
        ----------
        model : LoopModel
            The current model, without the effect.
        data : LoopData
            The record (top speed needed); only its calibration part is used.

        Returns
        -------
        list of dict
            ``{"variant": "motor", "droop_rad_s_per_nm", "inertia_kg_m2", "command_rad_s"}`` sets.
        """
        from .. import model as M
        from drillpy import _core
        chs = M.state_channels(model, data)
        tr = np.flatnonzero(data.valid & (data.t < data.t_split))
        sim = M.simulation(model.engine_config())
        cv = model.effects.get("viscous_damping", {}).get("bit_viscous_nms", 0.0)
        tsf = model.effects.get("string_friction", {}).get("string_friction_nm", 0.0)
        i = tr[::max(1, int(round(0.005 / data.dt)))]
        top, dtop, v = chs["top"][i], chs["dtop"][i], chs["v"][i]
        total = chs["T"][i] + cv * v + tsf * np.sign(v)  # the torque on the bit, outside the sensor included
        ttop = np.asarray(_core.top_torque_from_bit(sim, v, chs["a"][i], total, top, dtop))
        jmin = 1.5 * RESOLVED * M.motor_inertia_floor(model)
        mean_top, mean_t = float(np.mean(top)), float(np.mean(ttop))
        starts = []
        A = np.column_stack([dtop, top, -np.ones(i.size)])
        (J, c, c_om), *_ = np.linalg.lstsq(A, -ttop, rcond=None)
        if J > jmin and c > 0:
            starts.append({"variant": "motor", "droop_rad_s_per_nm": float(np.clip(1.0 / c, 1e-3, 1e3)),
                           "inertia_kg_m2": float(J), "command_rad_s": float(c_om / c)})
        slope, icpt = np.polyfit(ttop, top, 1)  # quasi-static droop: Omega = Omega_c - T_top / c_m
        if slope < 0:
            droop = float(np.clip(-slope, 1e-3, 1e3))
            for tau in (0.01, 0.05):
                starts.append({"variant": "motor", "droop_rad_s_per_nm": droop,
                               "inertia_kg_m2": max(tau / droop, jmin), "command_rad_s": float(icpt)})
        for droop in (1.0, 4.0):
            starts.append({"variant": "motor", "droop_rad_s_per_nm": droop, "inertia_kg_m2": max(0.05 / droop, jmin),
                           "command_rad_s": mean_top + droop * mean_t})
        # each behind a soft and a stiff coupling; the rotor's inertia at least 0.02 kg m^2 behind the
        # soft one (the order that shields the rig's 3 Hz mode from the motor's damping)
        return [dict(s, coupling_stiffness_nm_rad=k, inertia_kg_m2=max(s["inertia_kg_m2"], j))
                for s in starts for k, j in ((30.0, 0.02), (COUPLING[1] * 0.99, 0.0))]

    def declared(self, cfg):
        """The motor variant when ``cfg.top_drive`` is a motor (droop 1 / ``slope_nms_rad``,
        its ``inertia_kg_m2``, the command ``operation.top_speed_rad_s``), else None; see
        :meth:`Effect.declared`.

        Parameters
        ----------
        cfg : dict or Configuration
            The declared engine configuration.
        """
        cfg = view(cfg)
        td = cfg.top_drive
        if td.type != "motor":
            return None
        p = {"variant": "motor", "droop_rad_s_per_nm": 1.0 / float(td.slope_nms_rad),
             "inertia_kg_m2": float(td.inertia_kg_m2), "command_rad_s": float(cfg.operation.top_speed_rad_s)}
        secs = cfg.string.sections
        if secs and secs[0].get("name") == "coupling":
            c = {"string": {"sections": [secs[0].to_dict()], "lumped_inertias": []}}  # a holder remove_coupling edits
            p["coupling_stiffness_nm_rad"] = remove_coupling(c)
        return p

    def strip(self, cfg):
        """Remove ``top_drive`` (the ideal drive at ``operation.top_speed_rad_s``) and a coupling
        section; see :meth:`Effect.strip`.

        Parameters
        ----------
        cfg : dict
            Engine configuration, modified in place.
        """
        cfg.pop("top_drive", None)
        remove_coupling(cfg)

    def configure(self, cfg, p, model):
        """A ``"motor"`` top drive (slope c_m = 1 / droop [N m s/rad], inertia J_m [kg m^2])
        commanded at Omega_c (``operation.top_speed_rad_s`` [rad/s]), behind the coupling section of
        stiffness k_c when ``p`` has one; the kinematic variant leaves
        the configuration as is (its top speed is a series, :meth:`top_state`). See
        :meth:`Effect.configure`.

        Parameters
        ----------
        cfg : dict
            Engine configuration, modified in place.
        p : dict
            ``{"variant", "droop_rad_s_per_nm", "inertia_kg_m2", "command_rad_s"}``.
        model : LoopModel or None
            Not used.
        """
        if p.get("variant") == "measured":
            return
        cfg["top_drive"] = {"type": "motor", "slope_nms_rad": 1.0 / p["droop_rad_s_per_nm"],
                            "inertia_kg_m2": p["inertia_kg_m2"]}
        cfg["operation"]["top_speed_rad_s"] = float(p["command_rad_s"])
        if "coupling_stiffness_nm_rad" in p:
            add_coupling(cfg, p["coupling_stiffness_nm_rad"])

    def top_state(self, p, model, chs, idx):
        """The measured top speed [rad/s] at the restarts; for the motor its rate left NaN (the
        engine takes it from the motor equation, not the noisy record) and no driving series; for the
        kinematic variant the measured rate [rad/s^2] and the measured top speed as the driving
        series. See :meth:`Effect.top_state`.

        Parameters
        ----------
        p : dict
            The effect's values (``p["variant"]``).
        model : LoopModel
            Not used.
        chs : dict
            State channels (``top`` [rad/s], ``dtop`` [rad/s^2]).
        idx : array_like of int
            Restart sample indices.
        """
        if p.get("variant") == "measured":
            return chs["top"][idx], chs["dtop"][idx], chs["top"]
        return chs["top"][idx], np.full(len(idx), np.nan), None

    def inject(self, truth, p):
        """Give the truth a motor top drive, its command raised above the declared top speed by the
        droop at the steady torque on the bit there (the law at zero acceleration plus the viscous
        torque): the loaded top turns near the declared speed; see
        :meth:`Effect.inject`.

        Parameters
        ----------
        truth : drillpy.loop.synthetic.Truth
            The synthetic truth (its configuration replaced by a changed copy).
        p : dict
            ``{"slope_nms_rad": c_m [N m s/rad], "inertia_kg_m2": J_m [kg m^2]}`` (defaults 0.25 and
            0.02).
        """
        from drillpy.model.simulation import law_torque
        c = view(truth.cfg)
        om0, w0 = float(c.operation.top_speed_rad_s), float(c.operation.wob_n)
        t_mean = float(law_torque(c.law.to_dict(), om0, 0.0, w0)[0]) + c.operation.get("bit_viscous_nms", 0.0) * om0
        truth.cfg = c.replace({"operation.top_speed_rad_s": om0 + t_mean / p["slope_nms_rad"]},  # above the mean by the droop
                              top_drive={"type": "motor", "slope_nms_rad": p["slope_nms_rad"],
                                         "inertia_kg_m2": p["inertia_kg_m2"]}).to_dict()


EFFECT = TopDriveDynamics()
