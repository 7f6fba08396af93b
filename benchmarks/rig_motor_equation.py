"""Does sample 175's top speed follow an inertial motor? The open-loop motor's equation
J_m Omega' = c_m (Omega_c - Omega) - T_top (drill/topdrive.hpp) is linear in (J_m, c_m, c_m Omega_c)
given the top speed, its rate and the torque the string puts on the top; this script fits it by least
squares on the cleaned record (every valid sample, excluded samples interpolated), with the top
torque taken as the measured torque on bit shifted by 0-50 ms (the string's torque is nearly uniform
at the rig's 2.9 Hz: the bar's own inertia is a fortieth of the disk's) and as GJ/L times the
high-passed twist integrated from the two encoders.

    PYTHONPATH=python python3 benchmarks/rig_motor_equation.py [RECORD]

A J_m near zero (or negative) says the recorded top speed is a static droop of the torque on the
scale of the short horizons, not the response of a rotor with inertia; the whole-rig model of
``drillpy analyze`` needs J_m of about 0.019 kg m^2 (behind a compliant coupling) to keep the
stick-slip cycle in its long run (docs/records.md, docs/loop.md).
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy import signal as sps

from drillpy.records.cleaning import clean
from drillpy.records.io import read_record

RECORD = Path(__file__).resolve().parents[2] / "shared" / "data" / "testrig" / "sample175_0-40s.mat"
GJ_L = 3.08  # N m/rad: the bar of Table 5.1


def fit(top, dtop, t_top):
    """(J_m, c_m, Omega_c, R^2) of J Omega' + c Omega - c Omega_c = -T_top."""
    A = np.column_stack([dtop, top, -np.ones(top.size)])
    x, *_ = np.linalg.lstsq(A, -t_top, rcond=None)
    r2 = 1.0 - np.sum((A @ x + t_top) ** 2) / np.sum((t_top - t_top.mean()) ** 2)
    return x[0], x[1], x[2] / x[1], r2


def main(argv=None) -> int:
    path = Path((argv or sys.argv[1:] or [str(RECORD)])[0])
    rec = clean(read_record(path))[0]
    ok = rec.valid("top_speed", "bit_speed", "torque_on_bit")
    i = np.arange(len(rec))

    def filled(x):
        return np.interp(i, i[ok], x[ok])

    top, v, T = filled(rec.top_speed), filled(rec.bit_speed), filled(rec.torque_on_bit)
    dt = rec.dt
    n = max(7, int(round(0.031 / dt)) | 1)
    dtop = sps.savgol_filter(top, n, 4, deriv=1, delta=dt)
    b, a = sps.butter(2, 0.2 * 2 * dt, "high")
    twist = sps.filtfilt(b, a, np.cumsum(top - v) * dt)
    core = slice(int(0.2 / dt), len(rec) - int(0.2 / dt))
    print(f"record: {path.name}, {len(rec)} samples at {1 / dt:.0f} Hz; fit of J_m Omega' = c_m (Omega_c - Omega) "
          "- T_top")
    print(f"{'top torque':<34} {'lag ms':>6} {'J_m kg m^2':>11} {'c_m N m s/rad':>14} {'Omega_c RPM':>12} {'R^2':>6}")
    for name, t_top in (("measured torque on bit", T), ("GJ/L x encoder twist (high-passed)", GJ_L * twist + T.mean())):
        for lag_ms in (0, 10, 20, 30, 50):
            k = int(round(lag_ms * 1e-3 / dt))
            J, c, om, r2 = fit(top[core], dtop[core], np.roll(t_top, k)[core])
            print(f"{name:<34} {lag_ms:>6} {J:>11.4f} {c:>14.3f} {om * 30 / np.pi:>12.0f} {r2:>6.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
