"""One run with a given top drive, recorded: the stick-slip episode with and without a controller
and the motor torque the drive demands (issue 15, item 3).

The motor torque u is not an engine output; it follows from the drive's equation of motion
J Omega' = u - T_top (docs/control.md) on the recorded series:

    u_k = J (Omega_{k+1} - Omega_k) / h + (T_top,k + T_top,k+1) / 2

which is the mean of u over the output interval h (exact for the integral of J Omega'; the
string torque by the trapezoidal rule). The ideal drive has no motor model: its u is the string's
top torque (a drive that holds its speed supplies it).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from drillpy.model.configuration import Configuration
from drillpy.model.simulation import simulate


@dataclass
class Episode:
    """A recorded run with one top drive.

    Attributes
    ----------
    label : str
        The drive's label.
    top_speed_command : float
        Commanded top speed [rad/s].
    t, bit_speed, top_speed, top_torque : numpy.ndarray
        Time [s], bit and top speeds [rad/s], string torque at the top [N m].
    t_motor, motor_torque : numpy.ndarray
        Mid-interval times [s] and the interval-mean motor torque [N m] (module docstring).
    severity, stick_fraction : float
        SS (Eq. 3.4) and the stick fraction of the run's metric window.
    torque_limit : float or None
        The drive's motor torque limit [N m].
    """
    label: str
    top_speed_command: float
    t: np.ndarray
    bit_speed: np.ndarray
    top_speed: np.ndarray
    top_torque: np.ndarray
    t_motor: np.ndarray
    motor_torque: np.ndarray
    severity: float
    stick_fraction: float
    torque_limit: float | None

    def peak_motor_torque(self, t0: float) -> float:
        """The largest |u| [N m] from ``t0`` on.

        Parameters
        ----------
        t0 : float
            Start of the window [s] (e.g. the transient).

        Returns
        -------
        float
            max |u| over the window.
        """
        return float(np.max(np.abs(self.motor_torque[self.t_motor >= t0])))

    def summary(self, t0: float) -> dict:
        """JSON-ready numbers of the run.

        Parameters
        ----------
        t0 : float
            Start of the metric window [s].

        Returns
        -------
        dict
            ``label``, ``top_speed_rad_s``, ``ss``, ``stick_fraction``, ``peak_motor_torque_nm``,
            ``mean_motor_torque_nm``, ``torque_limit_nm`` and ``within_limit``.
        """
        u = self.motor_torque[self.t_motor >= t0]
        peak = self.peak_motor_torque(t0)
        return {"label": self.label, "top_speed_rad_s": self.top_speed_command, "ss": self.severity,
                "stick_fraction": self.stick_fraction, "peak_motor_torque_nm": peak,
                "mean_motor_torque_nm": float(np.mean(u)), "torque_limit_nm": self.torque_limit,
                "within_limit": None if self.torque_limit is None else bool(peak <= self.torque_limit * (1 + 1e-9))}


def motor_torque(t: np.ndarray, top_speed: np.ndarray, top_torque: np.ndarray,
                 inertia: float | None) -> tuple[np.ndarray, np.ndarray]:
    """The interval-mean motor torque of a recorded run (module docstring).

    Parameters
    ----------
    t : numpy.ndarray
        Output times [s].
    top_speed : numpy.ndarray
        Top (motor) speed [rad/s].
    top_torque : numpy.ndarray
        String torque at the top [N m].
    inertia : float or None
        Drive inertia J [kg m^2]; None for the ideal drive (u = T_top).

    Returns
    -------
    tuple of numpy.ndarray
        Mid-interval times [s] and u [N m].
    """
    h = np.diff(t)
    tm = 0.5 * (t[1:] + t[:-1])
    mean_torque = 0.5 * (top_torque[1:] + top_torque[:-1])
    if inertia is None:
        return tm, mean_torque
    return tm, inertia * np.diff(top_speed) / h + mean_torque


def run_episode(cfg: dict, label: str, drive: dict | None, top_speed: float, wob: float | None = None) -> Episode:
    """Run the configuration with ``drive`` at one top speed, recorded.

    Parameters
    ----------
    cfg : dict
        The configuration (duration, transient, start).
    label : str
        The drive's label.
    drive : dict or None
        ``top_drive`` block (None: the configuration's own drive).
    top_speed : float
        Commanded top speed [rad/s].
    wob : float, optional
        WOB [N] (default the configuration's).

    Returns
    -------
    Episode
        The series, the motor torque and the run's metrics.
    """
    c = Configuration.of(cfg).with_overrides(top_drive=drive)
    r = simulate(c, top_speed, wob)
    td = c.top_drive
    inertia = td.inertia_kg_m2 if td.type in ("controlled", "motor") else None
    tm, u = motor_torque(np.asarray(r.t), np.asarray(r.top_speed), np.asarray(r.top_torque), inertia)
    limit = td.controller.get("torque_limit_nm") if td.type == "controlled" else None
    return Episode(label, float(top_speed), np.asarray(r.t), np.asarray(r.bit_speed), np.asarray(r.top_speed),
                   np.asarray(r.top_torque), tm, u, float(r.severity), float(r.stick_fraction), limit)
