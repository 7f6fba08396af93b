#!/usr/bin/env python3
"""A third independent simulator of the thesis test rig for checking ``drillpy loop``: a continuous
bar by a Rayleigh-Ritz expansion, Kelvin-Voigt material damping, an arctan-Stribeck law with a
viscous part, a stiff implicit integrator (``scipy.integrate.solve_ivp``, Radau) with events for
stick and break-away, and realistic sensors (quantized encoders differentiated, a load cell).

It shares no code with drillpy (NumPy and SciPy only; drillpy is not imported), and its simulation
none with ``independent_rig.py`` (lumped segments, modal damping, Tucker-Wang, semi-implicit Euler;
only the measure of a record, :func:`metrics`, and the CSV writer, :func:`write_csv`, are that
module's, so that the checks read every simulator's records alike) or
``stribeck_rig.py`` (lumped segments, Rayleigh damping, exponential Stribeck, exact linear step):

* **Bar** (thesis Table 5.1): steel, L = 1.7 m, radius 2.5 mm (J_p = pi r^4 / 2), density 7850
  kg/m^3, G J_p / L = 3.08 N m/rad. A *continuous* bar: the twist angle along it is expanded as
  theta(x, t) = theta_top (1 - x/L) + theta_disk x/L + sum_i q_i sin(i pi x / L), i = 1..``N_BUBBLE``
  (Rayleigh-Ritz: the static shape plus sine "bubble" functions that vanish at both ends), with the
  consistent mass matrix rho J_p int N_a N_b dx and the stiffness G J_p int N_a' N_b' dx, both in
  closed form. The disk (3.921 kg, radius 0.069 m: J_d = 9.33e-3 kg m^2) sits on the bottom end.
  The first natural frequency (top clamped) is the root of beta L tan(beta L) = J_bar / J_d,
  omega = beta sqrt(G / rho): 2.889 Hz (tests/python/test_third_rig.py checks the expansion
  against it).
* **Damping**: Kelvin-Voigt (the bar's shear stress has a strain-rate part eta G dgamma/dt), i.e.
  C = eta K over the bar's shapes, eta = 2 ``ZETA1`` / omega_1 with ``ZETA1`` = 0.04 on the first
  mode (the bubbles are overdamped, as a Kelvin-Voigt bar's high modes are). Rigid rotation is
  not damped (K annihilates it). A bearing drag ``C_BEARING`` on the disk is outside the sensor.
* **Bit-rock law** (arctan-Stribeck with a viscous part; v the bit speed in rad/s, W the WOB):

      T(v, W) = W / W_ref [ (2/pi) atan(v / v_r) (T_c + (T_s - T_c) (1 - (2/pi) atan(|v| / v_s))) + c_l v ]

  T_s 2.7 N m, T_c 1.3 N m, v_s 3 rad/s, v_r 0.01 rad/s (regularization at zero speed),
  c_l 0.004 N m s/rad, W_ref 557.1 N: 2.56 N m at its maximum (0.24 rad/s), 1.64 N m at 8.47 rad/s
  with a slope of -0.029 N m s/rad there, 1.52 N m at 17 rad/s. The contact holds the bit (a true
  stick) while the torque that would accelerate it stays within T_s W / W_ref: a break-away torque
  (2.7 N m) above the sliding law's maximum (2.56 N m), which a regularized law (zero at rest) lacks,
  so that ``static_friction`` at 2.7 N m is a reading of this truth.
* **Stick and slip**: phases integrated separately by ``solve_ivp`` (Radau, rtol 1e-6, analytic
  Jacobian): in slip, a terminal event when |v| falls to ``STICK_BAND`` (then stick if the holding
  torque is within the capacity); in stick the bit's speed is zero and its angle frozen (the DOF removed), with a terminal
  event when the holding torque reaches the capacity (break-away). The stick is caught by a
  Karnopp band: a slipping bit whose speed falls below ``STICK_BAND`` = 0.05 rad/s (the
  regularized law would let it creep) is set to rest and held.
* **Top**: prescribed speed Omega = 8.47 rad/s; or (``compliant_motor``) a rotor J_r = 0.02 kg m^2
  driven by an open-loop motor T_m = c_m (Omega_c - omega_r), c_m = 0.1 N m s/rad, Omega_c =
  Omega + 1.85 / c_m (a mean top speed near 8.5 rad/s), through a coupling spring k_c = 6 N m/rad
  (damper 0.01 N m s/rad) to a hub J_h = 2e-3 kg m^2 on the bar's top: two inertias and a spring
  between them (modes 2.85 and 11.1 Hz).
* **WOB**: a smooth random multisine, W(t) = W0 (1 + 0.12 z(t)), z a unit-variance sum of 60
  cosines at 0.05-2 Hz with random phases (seeded); the law uses the constant W0 unless
  ``wob_coupling``.
* **Sensors** (the record: 5 s of settling dropped, then 32 s at 1000 Hz): the bit and top speeds
  are *differentiated encoder angles* (2^16 counts per revolution, the quantized angle
  backward-differenced at 1 kHz: a resolution of 0.096 rad/s, plus 0.02 rad/s electronic noise), the
  bit encoder on the disk (on the bit below the compliance with ``bit_compliance``; the top encoder
  on the rotor when there is one); the torque on bit is a
  load cell under the rock holder reading the contact torque (gain 1, offset 0, noise 0.02 N m);
  the WOB a load cell (noise 2 N). Optional low-pass: a 2nd-order Butterworth (``sosfilt``, causal,
  initialised at rest on the first value) on every channel.

Options (each a failure class of issue 29; values in SI):

====================== ================================================================
option                 model change
====================== ================================================================
bit_compliance         a torsional spring k_db = 20 N m/rad (damper 0.25 N m s/rad) between
                       the disk and a bit of J_b = 1.5e-3 kg m^2; the contact acts on the
                       bit, the bit encoder sits on it, the load cell on the rock (out
                       of the loop's catalogue; the nearest catalogue reading is a softer
                       string: k_db in series with 3.08 N m/rad is 2.68 N m/rad)
compliant_motor        the two-inertia motor above instead of the prescribed top speed
lowpass_hz             the sensor low-pass's cutoff (10 Hz in the cases)
wob_gain               the law at W_eff = W0 (1 + k (W(t)/W0 - 1)), k = 1 full / 0.5 half
bit_viscous            a viscous torque c_v v on the bit, outside the load cell; c_v = 0.02
                       N m s/rad, 18 % of the torque at the peak bit speed (about 19 rad/s)
gj_factor              the bar's G J times 0.88 (12 % softer than declared)
torque_gain/offset     the load cell reads 1.15 T + 0.15 N m
====================== ================================================================

    python3 benchmarks/third_rig.py --summary                              # clean record's metrics
    python3 benchmarks/third_rig.py --case wob_half --seed 3 --out rec.csv
    PYTHONPATH=python python3 benchmarks/loop_independent.py --simulator third --dir /tmp/third
"""
from __future__ import annotations

import argparse
import math
import sys
import time

import numpy as np
import scipy.linalg
import scipy.optimize
import scipy.signal
from scipy.integrate import solve_ivp

from independent_rig import metrics, write_csv  # the measure of a record and the record format, shared by the checks

# ----------------------------------------------------------------------------------- the rig
LENGTH_M = 1.7
RADIUS_M = 2.5e-3
DENSITY = 7850.0
GJ_OVER_L = 3.08                                  # N m/rad
J_P = math.pi * RADIUS_M ** 4 / 2                 # m^4
G_PA = GJ_OVER_L * LENGTH_M / J_P                 # Pa
J_BAR = DENSITY * J_P * LENGTH_M                  # the bar's own rotary inertia [kg m^2]
J_DISK = 0.5 * 3.921 * 0.069 ** 2                 # 9.33e-3 kg m^2
N_BUBBLE = 4
ZETA1 = 0.04
STICK_BAND = 0.05                                 # rad/s: Karnopp band, the bit is caught below it
C_BEARING = 0.002                                 # N m s/rad on the disk (always, not measured)
OMEGA0 = 8.47                                     # rad/s
W0 = 557.1                                        # N
W_REF = 557.1
WOB_STD = 0.12
WOB_BAND = (0.05, 2.0)                            # Hz
N_WOB_TONES = 60

# arctan-Stribeck law
LAW = {"Ts": 2.7, "Tc": 1.3, "vs": 3.0, "vr": 0.01, "cl": 0.004}

# motor (compliant_motor)
MOTOR = {"J_r": 0.02, "c_m": 0.1, "k_c": 6.0, "c_c": 0.01, "J_h": 2e-3, "T_mean": 1.85}
# disk-bit compliance (bit_compliance)
BIT = {"J_b": 1.5e-3, "k_db": 20.0, "c_db": 0.25}

FS_HZ = 1000.0
SETTLE_S = 5.0
DURATION_S = 32.0
ENCODER_COUNTS = 2 ** 16
NOISE = {"speed": 0.02, "torque": 0.02, "wob": 2.0}

#: Case options (the ``--case`` names; loop_independent.py's THIRD_CASES use them).
CASE_OPTIONS = {
    "clean": {},
    "bit_compliance": {"bit_compliance": True},
    "motor_lowpass": {"compliant_motor": True, "lowpass_hz": 10.0},
    "lowpass_wob": {"lowpass_hz": 10.0, "wob_gain": 1.0},
    "bit_viscous": {"bit_viscous": 0.018},
    "soft_string": {"gj_factor": 0.88},
    "wob_full": {"wob_gain": 1.0},
    "wob_half": {"wob_gain": 0.5},
    "load_cell": {"torque_gain": 1.15, "torque_offset": 0.15},
}


def law(v: float, w_fac: float = 1.0) -> float:
    """The arctan-Stribeck torque [N m] at bit speed v [rad/s] and W = w_fac W_ref (odd in v)."""
    p = LAW
    shape = p["Tc"] + (p["Ts"] - p["Tc"]) * (1.0 - (2.0 / math.pi) * math.atan(abs(v) / p["vs"]))
    return w_fac * ((2.0 / math.pi) * math.atan(v / p["vr"]) * shape + p["cl"] * v)


def law_slope(v: float, w_fac: float = 1.0) -> float:
    """dT/dv of :func:`law` [N m s/rad]."""
    p = LAW
    a = (2.0 / math.pi) * math.atan(v / p["vr"])
    da = (2.0 / math.pi) * (1.0 / p["vr"]) / (1.0 + (v / p["vr"]) ** 2)
    shape = p["Tc"] + (p["Ts"] - p["Tc"]) * (1.0 - (2.0 / math.pi) * math.atan(abs(v) / p["vs"]))
    dshape = -(p["Ts"] - p["Tc"]) * (2.0 / math.pi) / p["vs"] / (1.0 + (v / p["vs"]) ** 2) * (1.0 if v >= 0 else -1.0)
    return w_fac * (da * shape + a * dshape + p["cl"])


# --------------------------------------------------------------------------- the bar (Ritz)
def bar_matrices(gj_factor: float = 1.0):
    """Consistent mass and stiffness of the bar over (theta_top, theta_disk, q_1..q_NB)."""
    n = 2 + N_BUBBLE
    m = np.zeros((n, n))
    k = np.zeros((n, n))
    m[0, 0] = m[1, 1] = 1.0 / 3.0
    m[0, 1] = m[1, 0] = 1.0 / 6.0
    k[:2, :2] = [[1.0, -1.0], [-1.0, 1.0]]
    for i in range(1, N_BUBBLE + 1):
        j = 1 + i
        m[0, j] = m[j, 0] = 1.0 / (i * math.pi)                      # int (1 - s) sin(i pi s) ds
        m[1, j] = m[j, 1] = (-1.0) ** (i + 1) / (i * math.pi)        # int s sin(i pi s) ds
        m[j, j] = 0.5
        k[j, j] = 0.5 * (i * math.pi) ** 2                           # int (i pi cos)^2 ds
    return J_BAR * m, GJ_OVER_L * gj_factor * k


def first_frequency_exact(gj_factor: float = 1.0) -> float:
    """The continuous bar's first natural frequency [Hz], top clamped, the disk on the bottom:
    beta L tan(beta L) = J_bar / J_disk, omega = beta sqrt(G gj_factor / rho)."""
    r = J_BAR / J_DISK
    bl = scipy.optimize.brentq(lambda b: b * math.tan(b) - r, 1e-9, math.pi / 2 - 1e-12)
    c = math.sqrt(G_PA * gj_factor / DENSITY)
    return bl / LENGTH_M * c / (2 * math.pi)


class Rig:
    """The assembled linear structure: degrees of freedom, M, K, C, and where the contact acts."""

    def __init__(self, opts: dict):
        self.opts = opts
        gj = opts.get("gj_factor", 1.0)
        mb, kb = bar_matrices(gj)
        names = ["top", "disk"] + [f"q{i}" for i in range(1, N_BUBBLE + 1)]
        extra = []
        if opts.get("bit_compliance"):
            extra.append("bit")
        if opts.get("compliant_motor"):
            extra.append("rotor")
        names += extra
        n = len(names)
        M = np.zeros((n, n))
        K = np.zeros((n, n))
        nb = 2 + N_BUBBLE
        M[:nb, :nb] = mb
        K[:nb, :nb] = kb
        # first mode of the clamped bar with its disk: eta from ZETA1
        Mc = mb[1:, 1:].copy()
        Mc[0, 0] += J_DISK
        w1 = math.sqrt(np.min(np.real(scipy.linalg.eigvals(kb[1:, 1:], Mc))))
        eta = 2 * ZETA1 / w1
        C = np.zeros((n, n))
        C[:nb, :nb] = eta * kb
        M[1, 1] += J_DISK
        C[1, 1] += C_BEARING + opts.get("bit_viscous", 0.0) * (0 if opts.get("bit_compliance") else 1)
        idx = {nm: i for i, nm in enumerate(names)}
        self.contact = idx["disk"]
        if opts.get("bit_compliance"):
            b, d = idx["bit"], idx["disk"]
            M[b, b] += BIT["J_b"]
            for mat, val in ((K, BIT["k_db"]), (C, BIT["c_db"])):
                mat[b, b] += val
                mat[d, d] += val
                mat[b, d] -= val
                mat[d, b] -= val
            C[b, b] += opts.get("bit_viscous", 0.0)
            self.contact = b
        self.motor = bool(opts.get("compliant_motor"))
        if self.motor:
            r, t = idx["rotor"], idx["top"]
            M[r, r] += MOTOR["J_r"]
            M[t, t] += MOTOR["J_h"]
            for mat, val in ((K, MOTOR["k_c"]), (C, MOTOR["c_c"])):
                mat[r, r] += val
                mat[t, t] += val
                mat[r, t] -= val
                mat[t, r] -= val
            self.free = list(range(n))
            self.top_encoder = r
        else:
            self.free = [i for i in range(n) if i != idx["top"]]
            self.top_encoder = idx["top"]
        self.names, self.idx, self.n = names, idx, n
        self.M, self.K, self.C = M, K, C
        self.w1 = w1
        self.eta = eta

    def natural_frequencies_hz(self) -> np.ndarray:
        """Undamped natural frequencies of the free DOFs (top clamped when the top is prescribed)."""
        f = self.free
        w2 = np.real(scipy.linalg.eigvals(self.K[np.ix_(f, f)], self.M[np.ix_(f, f)]))
        return np.sort(np.sqrt(np.abs(w2))) / (2 * math.pi)


def wob_function(seed: int):
    """W(t) [N]: W0 (1 + WOB_STD z(t)), z a unit-variance random multisine (smooth, seeded)."""
    rng = np.random.default_rng([seed, 303])
    f = np.exp(rng.uniform(math.log(WOB_BAND[0]), math.log(WOB_BAND[1]), N_WOB_TONES))
    ph = rng.uniform(0, 2 * math.pi, N_WOB_TONES)
    a = np.full(N_WOB_TONES, math.sqrt(2.0 / N_WOB_TONES))
    w = 2 * math.pi * f

    def W(t):
        return W0 * (1.0 + WOB_STD * float(np.dot(a, np.cos(w * t + ph))))
    return W


def simulate(opts: dict, seed: int = 1, duration_s: float = DURATION_S, settle_s: float = SETTLE_S,
             fs_hz: float = FS_HZ, rtol: float = 1e-6) -> dict:
    """Simulate the rig with the options ``opts`` (keys of the table in the module docstring).

    Returns the true (noise-free, unfiltered) signals at fs_hz from t = 0 (settling included):
    time_s, angle arrays of every DOF ``theta`` (n_dof x n_t), speeds ``omega``, contact torque
    ``torque`` [N m], WOB ``wob`` [N], a ``stuck`` flag per sample, and the rig (``rig``).
    """
    rig = Rig(opts)
    W = wob_function(seed)
    kw = opts.get("wob_gain", 0.0)
    n, M, K, C = rig.n, rig.M, rig.K, rig.C
    c = rig.contact
    motor = rig.motor
    top = rig.idx["top"]
    if motor:
        c_m = MOTOR["c_m"]
        om_c = OMEGA0 + MOTOR["T_mean"] / c_m
        rot = rig.idx["rotor"]

    def wfac(t):
        return (1.0 + kw * (W(t) / W0 - 1.0)) * W0 / W_REF if kw else W0 / W_REF

    # phase systems: the free DOFs, minus the contact DOF while stuck
    def system(stuck: bool):
        f = [i for i in rig.free if not (stuck and i == c)]
        p = [i for i in range(n) if i not in f]     # prescribed: top (speed OMEGA0) and/or stuck bit (0)
        Mff = M[np.ix_(f, f)]
        Minv = np.linalg.inv(Mff)
        Kff, Cff = K[np.ix_(f, f)], C[np.ix_(f, f)]
        Kfp, Cfp = K[np.ix_(f, p)], C[np.ix_(f, p)]
        nf = len(f)
        jc = f.index(c) if c in f else None
        jr = f.index(rot) if motor else None
        A = np.zeros((2 * nf, 2 * nf))
        A[:nf, nf:] = np.eye(nf)
        A[nf:, :nf] = -Minv @ Kff
        A[nf:, nf:] = -Minv @ Cff
        if motor:
            A[nf:, nf + jr] -= Minv[:, jr] * c_m
        return f, p, nf, jc, jr, Minv, Kff, Cff, Kfp, Cfp, A

    systems = {False: system(False), True: system(True)}

    def prescribed(p, t, x_stuck):
        xp = np.array([OMEGA0 * t if i == top else x_stuck for i in p])
        vp = np.array([OMEGA0 if i == top else 0.0 for i in p])
        return xp, vp

    def holding_torque(t, y, stuck, x_stuck):
        """The torque the structure applies to the contact DOF (what the contact must balance when
        the bit is held at rest)."""
        f, p, nf, jc, jr, Minv, Kff, Cff, Kfp, Cfp, A = systems[stuck]
        x = np.zeros(n)
        v = np.zeros(n)
        x[f], v[f] = y[:nf], y[nf:]
        xp, vp = prescribed(p, t, x_stuck)
        x[p], v[p] = xp, vp
        return -(K[c] @ x) - (C[c] @ v)

    def make_rhs(stuck, x_stuck):
        f, p, nf, jc, jr, Minv, Kff, Cff, Kfp, Cfp, A = systems[stuck]

        def rhs(t, y):
            xp, vp = prescribed(p, t, x_stuck)
            force = -(Kfp @ xp) - (Cfp @ vp) if p else np.zeros(nf)
            if motor:
                force = force.copy()
                force[jr] += c_m * om_c
            if jc is not None:
                force = force.copy()
                force[jc] -= law(y[nf + jc], wfac(t))
            return A @ y + np.concatenate((np.zeros(nf), Minv @ force))

        def jac(t, y):
            if jc is None:
                return A
            J = A.copy()
            J[nf:, nf + jc] -= Minv[:, jc] * law_slope(y[nf + jc], wfac(t))
            return J
        return rhs, jac

    t_end = settle_s + duration_s
    t_out = np.arange(int(round(t_end * fs_hz)) + 1) / fs_hz
    X = np.full((n, t_out.size), np.nan)
    V = np.full((n, t_out.size), np.nan)
    T = np.full(t_out.size, np.nan)
    S = np.zeros(t_out.size, dtype=bool)

    # initial state: at rest, untwisted, the bit stuck (the top starts at OMEGA0 t, rotor at rest)
    x = np.zeros(n)
    v = np.zeros(n)
    stuck, x_stuck = True, 0.0
    slip_sign = 1.0
    t0 = 0.0
    n_stick = 0
    while t0 < t_end - 1e-12:
        f, p, nf, jc, jr, Minv, *_ = systems[stuck]
        y0 = np.concatenate((x[f], v[f]))
        rhs, jac = make_rhs(stuck, x_stuck)
        if stuck:
            cap = lambda t, y: LAW["Ts"] * wfac(t)  # noqa: E731
            ev = lambda t, y: abs(holding_torque(t, y, True, x_stuck)) - cap(t, y)  # noqa: E731
            ev.direction = 1
        else:
            ev = lambda t, y, sg=slip_sign: sg * y[nf + jc] - STICK_BAND  # noqa: E731
            ev.direction = -1           # the bit's speed falls into the stick band (not the start at zero)
        ev.terminal = True
        sel = (t_out > t0 + 1e-12) & (t_out <= t_end + 1e-12)
        sol = solve_ivp(rhs, (t0, t_end), y0, method="Radau", jac=jac, rtol=rtol, atol=1e-9,
                        t_eval=t_out[sel], events=ev, first_step=1e-5, max_step=0.01)
        if sol.status < 0:
            raise RuntimeError(sol.message)
        ts = np.asarray(sol.t, dtype=float)
        ys = np.asarray(sol.y, dtype=float).reshape(2 * nf, ts.size)
        k = np.flatnonzero(sel)[: ts.size]
        for j in range(ts.size):
            yy = ys[:, j]
            X[f, k[j]], V[f, k[j]] = yy[:nf], yy[nf:]
            xp, vp = prescribed(p, ts[j], x_stuck)
            X[p, k[j]], V[p, k[j]] = xp, vp
            S[k[j]] = stuck
            if stuck:
                Tw = LAW["Ts"] * wfac(ts[j])
                T[k[j]] = max(-Tw, min(Tw, holding_torque(ts[j], yy, True, x_stuck)))
            else:
                T[k[j]] = law(yy[nf + jc], wfac(ts[j]))
        if t0 == 0.0:
            X[:, 0], V[:, 0], T[0], S[0] = x, v, 0.0, True
        if sol.status == 0:
            break
        te, ye = sol.t_events[0][0], sol.y_events[0][0]
        x[f], v[f] = ye[:nf], ye[nf:]
        xp, vp = prescribed(p, te, x_stuck)
        x[p], v[p] = xp, vp
        if stuck:                       # break-away
            stuck = False
            v[c] = 0.0
            slip_sign = 1.0 if holding_torque(te, ye, True, x_stuck) > 0 else -1.0
        else:                           # the bit comes to rest: held if the capacity suffices
            v[c] = 0.0
            sys_s = systems[True]
            y_s = np.concatenate((x[sys_s[0]], v[sys_s[0]]))
            Th = holding_torque(te, y_s, True, x[c])
            if abs(Th) < LAW["Ts"] * wfac(te):
                stuck, x_stuck = True, x[c]
                n_stick += 1
            else:                       # the torque exceeds the capacity: it slips on, its way
                slip_sign = 1.0 if Th > 0 else -1.0
        t0 = te
    return {"time_s": t_out, "theta": X, "omega": V, "torque": T, "stuck": S,
            "wob": np.array([W(t) for t in t_out]), "rig": rig, "stick_events": n_stick,
            "settle_s": settle_s, "fs_hz": fs_hz}


def measure(sim: dict, opts: dict, seed: int = 1, noise: float = 1.0) -> dict:
    """The sensor chain: quantized encoders differentiated, the load cell, the WOB cells, an
    optional low-pass, noise; the settling dropped. Channels bit_speed, top_speed, torque_on_bit,
    wob [SI] on time_s from 0."""
    rng = np.random.default_rng([seed, 909])
    fs = sim["fs_hz"]
    rig = sim["rig"]
    q = 2 * math.pi / ENCODER_COUNTS

    def encoder(theta):
        counts = np.floor(theta / q)
        sp = np.empty_like(theta)
        sp[1:] = np.diff(counts) * q * fs
        sp[0] = sp[1]
        return sp
    ch = {"bit_speed": encoder(sim["theta"][rig.contact]),
          "top_speed": encoder(sim["theta"][rig.top_encoder]),
          "torque_on_bit": opts.get("torque_gain", 1.0) * sim["torque"] + opts.get("torque_offset", 0.0),
          "wob": sim["wob"].copy()}
    ch["bit_speed"] += noise * NOISE["speed"] * rng.standard_normal(ch["bit_speed"].size)
    ch["top_speed"] += noise * NOISE["speed"] * rng.standard_normal(ch["top_speed"].size)
    ch["torque_on_bit"] += noise * NOISE["torque"] * rng.standard_normal(ch["torque_on_bit"].size)
    ch["wob"] += noise * NOISE["wob"] * rng.standard_normal(ch["wob"].size)
    if opts.get("lowpass_hz"):
        sos = scipy.signal.butter(2, opts["lowpass_hz"], fs=fs, output="sos")
        for k in ch:
            zi = scipy.signal.sosfilt_zi(sos) * ch[k][0]
            ch[k], _ = scipy.signal.sosfilt(sos, ch[k], zi=zi)
    keep = sim["time_s"] >= sim["settle_s"] - 1e-9
    t = sim["time_s"][keep]
    return {"time_s": t - t[0], **{k: x[keep] for k, x in ch.items()}}


def true_metrics(sim: dict) -> dict:
    """:func:`metrics` of the true disk and top-encoder speeds after the settling."""
    keep = sim["time_s"] >= sim["settle_s"] - 1e-9
    rig = sim["rig"]
    return metrics(sim["omega"][rig.contact][keep], sim["omega"][rig.top_encoder][keep], sim["fs_hz"])


def make_record(case: str, seed: int, path: str, noise: float = 1.0, **over) -> dict:
    """Simulate the case ``case`` (a key of :data:`CASE_OPTIONS`, options overridden by ``over``),
    write the CSV record to ``path``; return the true metrics."""
    opts = {**CASE_OPTIONS[case], **over}
    sim = simulate(opts, seed=seed)
    rec = measure(sim, opts, seed=seed, noise=noise)
    met = true_metrics(sim)
    write_csv(rec, path, [f"third_rig.py (no drillpy code): case {case}, options {opts or 'none'}, seed {seed}, "
                          f"noise x{noise:g}",
                          f"Ritz bar ({N_BUBBLE} bubbles), Kelvin-Voigt zeta1 {ZETA1}, arctan-Stribeck {LAW}, "
                          f"Radau with stick events; truth metrics {met}"])
    return met


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--case", default="clean", choices=tuple(CASE_OPTIONS))
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--noise", type=float, default=1.0)
    ap.add_argument("--out", help="CSV file to write")
    ap.add_argument("--summary", action="store_true")
    a = ap.parse_args(argv)
    opts = CASE_OPTIONS[a.case]
    t0 = time.time()
    sim = simulate(opts, seed=a.seed)
    wall = time.time() - t0
    if a.out:
        rec = measure(sim, opts, seed=a.seed, noise=a.noise)
        write_csv(rec, a.out, [f"third_rig.py: case {a.case}, options {opts}, seed {a.seed}"])
    if a.summary or not a.out:
        mt = true_metrics(sim)
        keep = sim["time_s"] >= sim["settle_s"]
        T = sim["torque"][keep]
        v = sim["omega"][sim["rig"].idx["disk"]][keep]
        print(f"case {a.case}: modes {np.round(sim['rig'].natural_frequencies_hz()[:3], 2)} Hz; SS {mt['ss']:.3f}, "
              f"stick fraction {mt['stick_fraction']:.3f}, onsets {mt['stick_onsets_per_s']:.2f}/s, peak "
              f"{mt['spectral_peak_hz']:.2f} Hz; torque 5-95 % {np.percentile(T, 5):.2f}..{np.percentile(T, 95):.2f} "
              f"(mean {T.mean():.2f}); bit max {v.max():.2f}; top mean "
              f"{sim['omega'][sim['rig'].top_encoder][keep].mean():.3f}; sticks {sim['stick_events']}; wall {wall:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
