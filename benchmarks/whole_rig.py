"""A whole-rig truth: an independent simulator of the laboratory test rig of the thesis (F. F. Real 2018,
chapter 5), sensors and acquisition included, that writes records in the format of sample 175.

It shares no code with drillpy and does not import it (NumPy and SciPy only). It was written from the
thesis text (sections 5.1 and 5.3) and from statistics measured on sample 175, not from drillpy's engine.

Elements (each switchable, see ``ELEMENTS``; every parameter in ``DEFAULTS``, SI units inside)
------------------------------------------------------------------------------------------------
Degrees of freedom q = [theta_0 .. theta_N, phi_p]: N + 1 string nodes (0 the top drive, N the bit) and
the rock platform's rotation phi_p. M q'' + C q' + K q = B u + G^T lambda, u = [T_m, T_c].

* **Top drive** (``top_drive``): the rotor (J_m) sits on node 0 with half a segment's inertia.
  Open-loop DC motor (ESC at a fixed setting):  T_m = min(c_m (Omega_c - Omega_0), T_max).
  Its stall torque is c_m Omega_c (3.98 N m by default, below T_max = 8 N m: the motor saturates only
  when driven backwards). One-way hold (our choice): the rotor cannot be back-driven past zero speed
  unless the torque demands it. When Omega_0 reaches 0 from above, node 0 is held (constraint
  Omega_0 = 0) while the holding torque lambda_h the constraint needs lies in [0, T_hold] (T_hold =
  T_max: the ESC's brake); it is released forwards when lambda_h < 0 (the motor wins) and backwards
  when lambda_h > T_hold. Switched off, the top is an ideal drive: node 0 carries a 1e6 kg m^2 flywheel
  spinning at ``omega_top``.
  J_m = 0.013 kg m^2, not "a few 1e-3": with c_m = 0.22 N m s/rad an open-loop motor is a damper on
  the top, and with J_m of a few 1e-3 it damps the string's 3 Hz mode to zeta ~ 0.45 (eigenvalues of
  the linearized rig: a contact slope of -0.15 N m s/rad is needed to destabilize it, and then at
  1.8 Hz); every law whose torque range fits sample 175 then slides steadily at a high speed. The
  rotor's inertia shields the mode from the motor's damping once J_m omega_1 >~ c_m (J_m >~ 0.012);
  at 0.013 the rig stick-slips at 2.9 Hz. The price: the top lags the torque by ~90 ms where sample
  175 shows ~14 ms.
* **String**: the 1.7 m steel bar, radius 2.5 mm, GJ/L = 3.08 N m/rad, density 7800 kg/m^3, cut into
  ``n_seg`` equal Kelvin-Voigt segments (stiffness k_s = n_seg GJ/L, material damping c_s = beta k_s)
  with each segment's rotary inertia rho I_p L/n_seg split between its two end nodes. beta is set so
  that the first mode of the string clamped at the top (disk J_b = 9.33e-3 kg m^2 on node N) has the
  damping ratio ``zeta_string``: beta = 2 zeta_string / omega_1 (stiffness-proportional, so the
  kHz-range bar modes are overdamped, as a viscoelastic bar's would be).
* **Rock platform and torque load cell** (``platform``): the rock holder rotates on its platform,
  held by a rod against a cantilever load cell:
  J_p phi_p'' + c_p phi_p' + k_p phi_p = T_c, k_p = J_p (2 pi f_p)^2 (f_p = 20 Hz),
  c_p = 2 zeta_p sqrt(k_p J_p). The load cell reads k_p phi_p, in one direction only:
  reading = max(0, k_p phi_p) (the rod stays attached; the cell's one-sided reading is clipped).
  Switched off, the rock is fixed (J_p = 1e6) and the reading is the contact torque T_c itself.
* **Bit-rock contact**, v = Omega_N - Omega_p the bit's speed relative to the rock, W the WOB, r_b the
  bit radius (torque arm, 6 mm). Slipping (v != 0), a stretched-exponential Stribeck law:
      T_c = sign(v) W r_b mu(|v|) (1 + eta(t)),  mu(v) = mu_inf + (mu_0 - mu_inf) exp(-(v / v_s)^delta)
  (delta = 1: the exponential Stribeck; default 1.5, steeper at the operating speed, no flat top).
  Stuck (set-valued): constraint Omega_N = Omega_p; the contact torque is the constraint's reaction,
  |T_c| <= T_s = mu_s(tau) W r_b, mu_s(tau) = mu_static + mu_age ln(1 + tau / tau_age), tau the time
  stuck so far (static friction ageing: short sticks break near mu_static > mu_0, a long stick, i.e. a
  stall, holds more). A slip ending with v crossing 0 becomes a stick (momentum-conserving merge of bit
  and platform speeds) if the reaction it needs is within mu_static W r_b; a stick breaks when
  |T_c| > T_s, in the direction of T_c. W = 0 (lost contact): T_c = 0, no stick.
* **A law of the thesis instead** (``law``, default None: the Stribeck law above): a dict with
  ``type`` one of ``polynomial`` (Eq. 5.1: a0..a7, gain, ref_speed), ``polynomial_hysteretic`` (Eq. 5.3:
  the same with a0 = 0, beta1, beta2), ``tucker_wang`` (Eq. 3.1: c0, alpha0..alpha2) or ``hysteretic``
  (Eqs. 3.2-3.3: b0..b5, beta1, beta2), its coefficients in the law's ``speed_unit`` (``rpm`` or
  ``rad_s``, accelerations in speed_unit/s) and torques at the WOB ``wob_ref_n``:
  T_c = (W / wob_ref_n) T_law(v, a) (1 + eta), a the bit's relative acceleration over the last step.
  Written here from the thesis's equations (:func:`law_torque`), not from drillpy. Eq. (5.1) with
  a0 > 0 sticks (set-valued, as above) while |T_c| <= gain a0 W / wob_ref_n, without ageing; the
  regularized laws never enter the stuck mode: their steep rise from rest holds the bit.
* **Torque fluctuation** (``eta``): eta(t) an Ornstein-Uhlenbeck process (sd ``eta_sd``, correlation
  time ``eta_tau``), updated exactly every step.
* **Axial side** (``axial``; else W = ``wob0`` constant). Quasi-static axial compliance k_ax between
  the jack and the hole bottom: W = max(0, k_ax (z_j - h)). The jack is itself an open-loop DC drive at
  a constant supply voltage u (relative, ``jack_voltage``): z_j' = V_0 max(0, u s(t) - W/W_js) (free
  speed u V_0, stall force u W_js: its speed droops with the load). The bit cuts only while turning
  forwards and in contact, with an RGD-like depth of cut per revolution d = max(0, W - W_f) /
  (sigma rho(h)):  h' = d max(v, 0) / (2 pi). Hence the WOB rises at k_ax z_j' while the bit is stuck
  and falls while it slips fast; the jack's droop makes the WOB lead the bit's angle deficit.
* **Rock** (``rock``): the concrete's relative strength rho(h) along the hole: 1 + rock_sd x an AR(1)
  field of correlation length rock_corr (floored at 0.3), times hard aggregates (Poisson, agg_rate per
  m of depth, raised-cosine bumps of peak agg_factor over agg_size). Off, rho = 1.
* **Jack switch** (``jack_switch``): s(t) toggles between 1 and ``switch_low`` with dwell times drawn
  uniformly in [switch_dwell_min, switch_dwell_max] s (seeded): the slow WOB variation of a few tens
  of N. Off, s = 1. ``jack_steps`` [[t, u], ...]: the operator sets the supply to u at record time t
  (default: 1.12 at 27.6 s, which stalls the rig as sample 175 stalls at 28-30 s).
* **Stall and operator relief** (``operator``): the top stalls when the bit's static torque
  mu_s W r_b exceeds what the motor can deliver, c_m Omega_c (plus the rotor's overshoot): the top
  stops (below ``stall_speed``) with the bit stuck. After ``relief_wait`` s of stall the operator
  lowers the jack at ``relief_speed`` (z_j' = -relief_speed) and sets the supply back to
  ``jack_voltage``, until the bit turns again faster than Omega_c / 2; then the jack feeds again.
  Off, a stall lasts for ever.
* **Acquisition** (1 kHz): raw channels are the top and bit encoders (angles quantized to
  ``encoder_ppr`` counts per revolution when ``encoders``, speed = count difference x fs), the torque
  load cell and the WOB (three load cells, summed), each with white sensor noise (``noise_*``,
  x ``--noise``) and then the LabView second-order IIR low-pass: scipy.signal.butter(2, 10, fs=1000)
  + lfilter (``iir``). The top channel also carries broadband pickup noise added after the filter
  (``noise_top_post``, low-passed at 80 Hz), as the measured channel has.
* **Encoder artifacts** (``artifacts``, top channel, after the filter, as in sample 175 where they are
  5-ms sharp): isolated spikes (Poisson, ``spike_rate`` per s) ramping down to -100..-220 RPM over
  10-20 ms and jumping back; and, while the top is stalled (and in ``stretch`` windows given
  explicitly), the channel reads a baseline of about +40 RPM with such a spike every ~40 ms
  (between about -200 and +50 RPM, as the record at 28-30 s).

Integration: exact exponential (zero-order-hold) integration of the linear string-motor-platform system
in each contact mode, fixed step ``dt`` = 5e-5 s: x_{k+1} = Phi_m x_k + Gamma_m u_k with Phi_m =
expm(A_m dt) (four modes: bit stuck or not x top held or not; constrained modes by the projected
dynamics a = P M^-1 F, P = I - M^-1 G^T (G M^-1 G^T)^-1 G); the nonlinear inputs (motor torque, contact
torque, jack, cutting) are held over a step; mode changes are detected at the step's end (stick and
hold entries project the velocities onto the constraint, momentum-conserving). Start: the motor and
the untwisted string turn at Omega_c, the rock ``gap0`` below the bit, the jack lifting it (the
thesis's test procedure); 4 s of settling precede the record.

Default record (``--duration 40 --seed 1``, 3 s of CPU), ``--stats`` next to sample 175 (0-40 s; the
same statistics, computed the same way; "masked": +-80 ms around negative top-speed readings left out):

=========================================  ==================  ==================  ==================
                                           whole_rig, seed 1   seeds 1-5           sample 175
=========================================  ==================  ==================  ==================
top speed mean / sd [rad/s]                8.47 / 4.10         7.72-8.47/4.1-4.6   8.40 / 4.07
  artifacts masked                         8.73 / 3.64         8.15-8.73/3.6-4.2   9.08 / 3.23
bit speed mean / sd [rad/s]                8.51 / 5.14         7.80-8.51/5.1-6.0   8.40 / 6.09
torque mean / sd [N m]                     2.13 / 0.82         2.13-2.29/0.82-0.90 2.18 / 0.72
  sd with the stall left out               0.68                0.68-0.78           0.66
WOB mean / sd [N]                          571 / 71            571-589 / 62-76     563 / 77
stick-slip spectral peak [Hz]              2.93                2.93                2.69
stick fraction (< 5 % of mean)             0.093               0.093-0.144         0.113
droop top = a + b T: a, b                  19.2, -5.07         b -5.0..-5.2        18.4, -4.52
droop corr, top's lag [s]                  -0.98, 0.090        -0.97..-0.98, 0.090 -0.89, 0.014
WOB (>0.5 Hz) vs angle deficit: corr, lead 0.65, 0.046 s       0.65-0.84, 0.044 s  0.81, 0.036 s
  slope [N/rad]                            90                  90-113              138
=========================================  ==================  ==================  ==================

Known departures: the top lags the torque by ~90 ms, not ~14 ms (see Top drive), and its droop
regression is steeper (-5.1 against -4.5, the top's inertia); the cycle is 2.93 Hz against 2.69; the
stall (the 27.6 s supply step, ~1.5 s) holds 4.3-4.6 N m at ~770 N where sample 175 holds ~3.85 N m
at ~650 N (the rotor's overshoot is kept by the one-way hold).

Output: ``--out FILE.mat`` with Time_Sample_175_complete [s], Bit_Speed_Sample_175_complete [RPM],
Top_Speed_Sample_175_complete [RPM], Bit_Torque_Sample_175_complete [N m], WOB_Sample_175_complete [N]
(40000 x 1 columns for 40 s), and FILE.json beside it with the true parameters and elements.

    python3 benchmarks/whole_rig.py --out rec.mat --duration 40 --seed 1 --stats
    python3 benchmarks/whole_rig.py --out rec.mat --without artifacts,eta --set mu_static=1.2
    python3 benchmarks/whole_rig.py --stats-of /work/shared/data/testrig/sample175_0-40s.mat
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np
import scipy.io
import scipy.linalg
import scipy.signal

RPM = math.pi / 30.0  # rad/s per RPM
FS = 1000.0           # acquisition rate [Hz]
SUFFIX = "_Sample_175_complete"

ELEMENTS = ("top_drive", "platform", "axial", "rock", "jack_switch", "operator", "eta", "encoders", "iir", "noise",
            "artifacts")

DEFAULTS = {
    # top drive (open-loop DC motor)
    "J_m": 0.013, "c_m": 0.22, "omega_c": 18.1, "T_max": 8.0, "T_hold": 8.0, "omega_top": 8.7,
    # string
    "length": 1.7, "radius": 2.5e-3, "density": 7800.0, "GJ_L": 3.08, "n_seg": 10, "J_b": 9.33e-3,
    "zeta_string": 0.02,
    # rock platform and torque load cell
    "J_p": 0.02, "f_p": 20.0, "zeta_p": 0.05,
    # bit-rock contact (exponential Stribeck, set-valued stick)
    "r_b": 6e-3, "mu_static": 0.95, "mu_0": 0.87, "mu_inf": 0.3, "v_s": 11.0, "delta": 1.5,
    "mu_age": 0.08, "tau_age": 0.05,
    "eta_sd": 0.03, "eta_tau": 0.01, "law": None,
    # axial side
    "wob0": 560.0, "k_ax": 9e6, "V_0": 1.11e-3, "W_js": 690.0, "jack_voltage": 1.0,
    "jack_steps": [[27.6, 1.12]], "W_f": 0.0, "sigma": 4.56e6,
    "rock_sd": 0.35, "rock_corr": 5e-5, "agg_rate": 150.0, "agg_size": 3e-4, "agg_factor": 1.8,
    "switch_low": 0.93, "switch_dwell_min": 2.0, "switch_dwell_max": 6.0,
    "stall_speed": 0.3, "relief_wait": 1.2, "relief_speed": 5e-5,
    # acquisition
    "f_iir": 10.0, "encoder_ppr": 2000, "noise_speed": 0.3, "noise_torque": 0.01, "noise_wob": 2.0,
    "noise_top_post": 1.5, "spike_rate": 0.5, "stretch": [],
    # integration
    "dt": 5e-5, "settle": 4.0, "gap0": 3e-4,
}


# ------------------------------------------------------------------------------------------ the model
class Rig:
    """The linear part (matrices and the four modes' exact one-step maps) for one parameter set."""

    def __init__(self, p: dict, elements: set):
        self.p, self.el = p, elements
        n_seg = int(p["n_seg"])
        self.N = N = n_seg
        self.n = n = N + 2                       # string nodes 0..N, platform
        ip = math.pi * p["radius"] ** 4 / 2
        j_seg = p["density"] * ip * p["length"] / n_seg
        k_s = n_seg * p["GJ_L"]
        m = np.zeros(n)
        m[:N + 1] += 0.0
        for i in range(n_seg):
            m[i] += j_seg / 2
            m[i + 1] += j_seg / 2
        m[0] += p["J_m"] if "top_drive" in elements else 1e6
        m[N] += p["J_b"]
        m[N + 1] = p["J_p"] if "platform" in elements else 1e6
        ks = np.zeros((n, n))
        for i in range(n_seg):
            ks[i:i + 2, i:i + 2] += k_s * np.array([[1, -1], [-1, 1]])
        # beta from the top-clamped string's first mode
        kc, mc = ks[1:N + 1, 1:N + 1], m[1:N + 1]
        w1 = math.sqrt(scipy.linalg.eigh(kc, np.diag(mc), eigvals_only=True)[0])
        self.f1_clamped = w1 / (2 * math.pi)
        beta = 2 * p["zeta_string"] / w1
        K = ks.copy()
        C = beta * ks
        self.k_p = p["J_p"] * (2 * math.pi * p["f_p"]) ** 2
        if "platform" in elements:
            K[N + 1, N + 1] = self.k_p
            C[N + 1, N + 1] = 2 * p["zeta_p"] * math.sqrt(self.k_p * p["J_p"])
        self.m, self.K, self.C, self.k_s, self.c_s, self.beta = m, K, C, k_s, beta * k_s, beta
        B = np.zeros((n, 2))
        B[0, 0] = 1.0                            # motor torque on the top node
        B[N, 1], B[N + 1, 1] = -1.0, 1.0         # contact torque: brakes the bit, drives the platform
        self.B = B
        self.modes = {}
        for stuck in (False, True):
            for held in (False, True):
                self.modes[(stuck, held)] = self._mode(stuck, held)

    def _mode(self, stuck: bool, held: bool):
        n, N, dt = self.n, self.N, self.p["dt"]
        rows = []
        if stuck:
            g = np.zeros(n)
            g[N], g[N + 1] = 1.0, -1.0
            rows.append(g)
        if held:
            g = np.zeros(n)
            g[0] = 1.0
            rows.append(g)
        Minv = np.diag(1.0 / self.m)
        Bu = self.B.copy()
        if stuck:
            Bu[:, 1] = 0.0                      # the contact torque is the constraint's reaction
        P = np.eye(n)
        lam_x = lam_u = None
        proj = np.eye(n)
        if rows:
            G = np.array(rows)
            S = G @ Minv @ G.T
            Si = np.linalg.inv(S)
            P = np.eye(n) - Minv @ G.T @ Si @ G
            proj = P.copy()                     # velocity projection (an inelastic impulse)
            # lambda = -S^-1 G M^-1 (B u - K q - C v)
            L = -Si @ G @ Minv
            lam_x = np.hstack([L @ (-self.K), L @ (-self.C)])
            lam_u = L @ Bu
        A = np.zeros((2 * n, 2 * n))
        A[:n, n:] = np.eye(n)
        A[n:, :n] = P @ Minv @ (-self.K)
        A[n:, n:] = P @ Minv @ (-self.C)
        Bc = np.zeros((2 * n, 2))
        Bc[n:] = P @ Minv @ Bu
        aug = np.zeros((2 * n + 2, 2 * n + 2))
        aug[:2 * n, :2 * n] = A * dt
        aug[:2 * n, 2 * n:] = Bc * dt
        E = scipy.linalg.expm(aug)
        phi_aug = E[:2 * n, :]                  # [Phi | Gamma] acting on [x; u]
        return {"phi": np.ascontiguousarray(phi_aug), "lam_x": lam_x, "lam_u": lam_u, "proj": proj}


def _poly(a: list, u: float, ref: float) -> float:
    """The piecewise polynomial of Eq. (5.1) at the speed u >= 0 (breakpoints 1 % and 5 % of ref)."""
    if u <= 0.01 * ref:
        return a[0] + a[1] * u
    if u <= 0.05 * ref:
        return a[2] + a[3] * u
    return a[4] + u * (a[5] + u * (a[6] + u * a[7]))


def law_torque(v: float, acc: float, law: dict) -> float:
    """The contact torque of a thesis law (``law``, module docstring) at the reference WOB, for the
    bit's relative speed v [rad/s] and acceleration acc [rad/s^2]; odd in v (friction opposes the
    motion); at v = 0 the right limit."""
    k = 30.0 / math.pi if law.get("speed_unit", "rad_s") in ("rpm", "RPM") else 1.0
    u, a_u = abs(v) * k, acc * k
    sg = -1.0 if v < 0.0 else 1.0
    typ = law["type"]
    if typ in ("polynomial", "polynomial_hysteretic"):
        a = [float(law[f"a{i}"]) for i in range(8)]
        t = law["gain"] * _poly(a, u, law["ref_speed"])
        if typ == "polynomial_hysteretic":
            t *= 1.0 + law["beta1"] * sg * math.tanh(law["beta2"] * a_u)
        return sg * t
    if typ == "tucker_wang":
        return sg * law["c0"] * (math.tanh(law["alpha0"] * u) + law["alpha1"] * u / (1.0 + law["alpha2"] * u * u))
    if typ == "hysteretic":
        b0, b1, b2, b3, b4, b5 = (float(law[f"b{i}"]) for i in range(6))
        hump = b2 * u ** b4 / (1.0 + b3 * u ** b5) if u > 0.0 else 0.0
        h = 1.0 + law["beta1"] * sg * math.tanh(law["beta2"] * a_u)
        return sg * b0 * (math.tanh(b1 * u) + hump * h)
    raise ValueError(f"law.type = {typ!r}: polynomial, polynomial_hysteretic, tucker_wang or hysteretic")


def law_static(law: dict) -> float:
    """The break-away torque of a thesis law at its reference WOB: gain a0 for Eq. (5.1) with a0 > 0,
    else 0 (a regularized law never sticks)."""
    if law["type"] == "polynomial" and float(law["a0"]) > 0.0:
        return float(law["gain"]) * float(law["a0"])
    return 0.0


def mu_kinetic(v: float, p: dict) -> float:
    """The kinetic coefficient mu(|v|) of the Stribeck law (v in rad/s)."""
    return p["mu_inf"] + (p["mu_0"] - p["mu_inf"]) * math.exp(-(abs(v) / p["v_s"]) ** p["delta"])


def _switch_schedule(rng, t_end, p):
    times, levels, t, on = [], [], 0.0, True
    while t < t_end:
        times.append(t)
        levels.append(1.0 if on else p["switch_low"])
        t += rng.uniform(p["switch_dwell_min"], p["switch_dwell_max"])
        on = not on
    times.append(math.inf)
    return times, levels


def _rock_field(rng, p, el, depth):
    """Relative strength of the concrete along the hole: 1 + rock_sd x (AR(1) field, correlation length
    rock_corr), floored at 0.3; all ones without the ``rock`` element."""
    dz = p["rock_corr"] / 10
    n = int(depth / dz) + 2
    if "rock" not in el or p["rock_sd"] <= 0:
        return [1.0], 0.0
    a = math.exp(-dz / p["rock_corr"])
    e = scipy.signal.lfilter([math.sqrt(1 - a * a)], [1, -a], rng.standard_normal(n))
    f = np.maximum(0.3, 1 + p["rock_sd"] * e)
    # hard aggregates: Poisson along the depth, each a raised-cosine bump of strength over agg_size
    z = np.arange(n) * dz
    zk = rng.uniform(0.0, depth, rng.poisson(p["agg_rate"] * depth))
    for z0 in zk:
        m = (z >= z0) & (z < z0 + p["agg_size"])
        f[m] *= 1 + (p["agg_factor"] - 1) * 0.5 * (1 - np.cos(2 * math.pi * (z[m] - z0) / p["agg_size"]))
    return f.tolist(), 1 / dz


def simulate(params: dict | None = None, elements=None, duration: float = 40.0, seed: int = 1,
             noise: float = 1.0) -> dict:
    """Simulate the rig; return the recorded channels (SI: rad/s, N m, N) and the clean signals."""
    p = dict(DEFAULTS)
    p.update(params or {})
    el = set(ELEMENTS if elements is None else elements)
    bad = el - set(ELEMENTS)
    if bad:
        raise ValueError(f"unknown elements {sorted(bad)}")
    rig = Rig(p, el)
    rng = np.random.default_rng(seed)
    n, N, dt = rig.n, rig.N, p["dt"]
    settle = p["settle"]
    steps_per_sample = int(round(1.0 / (FS * dt)))
    if abs(steps_per_sample * dt * FS - 1) > 1e-9:
        raise ValueError("dt must divide 1 ms")
    n_settle = int(round(settle * FS))
    n_rec = int(round(duration * FS))
    n_out = n_settle + n_rec
    n_steps = n_out * steps_per_sample

    # state
    xa = np.zeros(2 * n + 2)                   # [q, v, T_m, T_c]
    tmp = np.empty(2 * n)
    # the test procedure: the motor turns freely (string untwisted), then the jack lifts the rock
    # against the bit from gap0 below it
    xa[n:n + N + 1] = p["omega_c"] if "top_drive" in el else p["omega_top"]
    stuck, held = False, False
    slip_dir = 1.0
    k_ax, r_b = p["k_ax"], p["r_b"]
    axial = "axial" in el
    W = p["wob0"] if "axial" not in el else 0.0
    z_j, h = -p["gap0"], 0.0
    relieving, stall_t = False, 0.0
    sw_t, sw_l = _switch_schedule(rng, settle + duration + 1, p) if "jack_switch" in el else ([0.0, math.inf],
                                                                                                [1.0])
    sw_i = 0
    steps = sorted((float(a) + settle, float(b)) for a, b in p["jack_steps"]) + [(math.inf, 1.0)]
    st_i = 0
    use_eta = "eta" in el
    eta, a_eta = 0.0, math.exp(-dt / p["eta_tau"])
    s_eta = p["eta_sd"] * math.sqrt(1 - a_eta * a_eta)
    chunk = 200000
    xi = rng.standard_normal(chunk)
    xi_i = 0
    c_m, om_c, T_max = p["c_m"], p["omega_c"], p["T_max"]
    motor = "top_drive" in el
    V0, W_js, W_f, sigma, u_jack = p["V_0"], p["W_js"], p["W_f"], p["sigma"], p["jack_voltage"]
    rock, inv_dz = _rock_field(rng, p, el, V0 * (settle + duration) * 1.5 + 1e-3)
    rock_last = len(rock) - 1
    mu_s, mu_0, mu_inf, v_s, delta = p["mu_static"], p["mu_0"], p["mu_inf"], p["v_s"], p["delta"]
    T_hold = p["T_hold"]
    mu_age, tau_age, t_stick = p["mu_age"], p["tau_age"], 0.0
    law = p["law"]
    if law is not None:  # a thesis law: its torques scale with W / wob_ref_n (mu r_b W <- T_law W / W_ref)
        law_torque(1.0, 0.0, law)  # refuses an unknown type before the run
        w_ref = float(law["wob_ref_n"])
        mu_s = law_static(law) / (w_ref * r_b)
        mu_age = 0.0
    acc_prev = 0.0
    operator = "operator" in el
    stall_speed, relief_wait, relief_speed = p["stall_speed"], p["relief_wait"], p["relief_speed"]
    relief_end = 0.5 * p["omega_c"]
    iN, ip_, i0 = n + N, n + N + 1, n
    two_pi = 2 * math.pi
    mode = rig.modes[(stuck, held)]
    phi = mode["phi"]

    rec = {k: np.empty(n_out) for k in ("th0", "thN", "om0", "omN", "omp", "phi_p", "T_c", "T_top", "W", "T_m")}
    rec_stuck = np.zeros(n_out, bool)
    rec_held = np.zeros(n_out, bool)
    rec_relief = np.zeros(n_out, bool)
    T_c = 0.0
    t = 0.0
    k_out = 0
    for k in range(n_steps):
        om0, omN, omp = xa[i0], xa[iN], xa[ip_]
        # ---- axial side (explicit)
        if axial:
            W = k_ax * (z_j - h)
            if W < 0.0:
                W = 0.0
            while t >= sw_t[sw_i + 1]:
                sw_i += 1
            if t >= steps[st_i][0]:
                u_jack = steps[st_i][1]
                st_i += 1
            if relieving:
                vj = -relief_speed
            else:
                vj = V0 * (u_jack * sw_l[sw_i] - W / W_js)
                if vj < 0.0:
                    vj = 0.0
            z_j += vj * dt
            v_rel = omN - omp
            if not stuck and v_rel > 0.0 and W > W_f:
                h += (W - W_f) / (sigma * rock[min(int(h * inv_dz), rock_last)]) * v_rel / two_pi * dt
        # ---- fluctuation
        if use_eta:
            if xi_i >= chunk:
                xi = rng.standard_normal(chunk)
                xi_i = 0
            eta = a_eta * eta + s_eta * xi[xi_i]
            xi_i += 1
        # ---- inputs
        if motor:
            T_m = c_m * (om_c - om0)
            if T_m > T_max:
                T_m = T_max
        else:
            T_m = 0.0
        if stuck:
            T_c = 0.0
        elif law is not None:
            v = omN - omp
            if v == 0.0 and mu_s > 0.0:
                T_c = slip_dir * mu_s * W * r_b * (1.0 + eta)
            else:
                T_c = W / w_ref * law_torque(v, acc_prev, law) * (1.0 + eta)
        else:
            v = omN - omp
            if v > 0.0:
                T_c = W * r_b * (mu_inf + (mu_0 - mu_inf) * math.exp(-(v / v_s) ** delta)) * (1.0 + eta)
            elif v < 0.0:
                T_c = -W * r_b * (mu_inf + (mu_0 - mu_inf) * math.exp(-(-v / v_s) ** delta)) * (1.0 + eta)
            else:
                T_c = slip_dir * W * r_b * mu_0 * (1.0 + eta)
        xa[2 * n] = T_m
        xa[2 * n + 1] = T_c
        v_before = omN - omp
        np.dot(phi, xa, out=tmp)
        xa[:2 * n] = tmp
        t += dt
        if law is not None:
            acc_prev = (xa[iN] - xa[ip_] - v_before) / dt
        # ---- mode changes
        changed = False
        if stuck:
            lam = mode["lam_x"][0] @ xa[:2 * n] + mode["lam_u"][0] @ xa[2 * n:]
            T_stick = -lam
            t_stick += dt
            if abs(T_stick) > (mu_s + mu_age * math.log1p(t_stick / tau_age)) * W * r_b:
                stuck, changed = False, True
                slip_dir = 1.0 if T_stick > 0 else -1.0
            else:
                T_c = T_stick
        else:
            v_after = xa[iN] - xa[ip_]
            if (v_before > 0.0 and v_after <= 0.0) or (v_before < 0.0 and v_after >= 0.0):
                trial = rig.modes[(True, held)]
                v_proj = trial["proj"] @ xa[n:2 * n]
                xx = np.concatenate([xa[:n], v_proj])
                lam = trial["lam_x"][0] @ xx + trial["lam_u"][0] @ xa[2 * n:]
                if abs(lam) <= mu_s * W * r_b:
                    xa[n:2 * n] = v_proj
                    stuck, changed, t_stick = True, True, 0.0
                    T_c = -lam
        if motor:
            if held:
                m_ = rig.modes[(stuck, True)]
                lam_h = (m_["lam_x"][-1] @ xa[:2 * n] + m_["lam_u"][-1] @ xa[2 * n:])
                if lam_h < 0.0 or lam_h > T_hold:
                    held, changed = False, True
            elif om0 > 0.0 and xa[i0] <= 0.0:
                trial = rig.modes[(stuck, True)]
                v_proj = trial["proj"] @ xa[n:2 * n]
                xx = np.concatenate([xa[:n], v_proj])
                lam_h = trial["lam_x"][-1] @ xx + trial["lam_u"][-1] @ xa[2 * n:]
                if 0.0 <= lam_h <= T_hold:
                    xa[n:2 * n] = v_proj
                    held, changed = True, True
        if changed:
            mode = rig.modes[(stuck, held)]
            phi = mode["phi"]
        # ---- operator
        if operator and axial:
            stalled = stuck and xa[i0] < stall_speed
            if relieving:
                if xa[iN] > relief_end:
                    relieving = False
            elif stalled:
                stall_t += dt
                if stall_t > relief_wait:
                    relieving, stall_t = True, 0.0
                    u_jack = p["jack_voltage"]          # the operator also sets the supply back
            else:
                stall_t = 0.0
        # ---- record (1 kHz)
        if (k + 1) % steps_per_sample == 0:
            rec["th0"][k_out] = xa[0]
            rec["thN"][k_out] = xa[N]
            rec["om0"][k_out] = xa[i0]
            rec["omN"][k_out] = xa[iN]
            rec["omp"][k_out] = xa[ip_]
            rec["phi_p"][k_out] = xa[N + 1]
            rec["T_c"][k_out] = T_c
            rec["T_top"][k_out] = rig.k_s * (xa[0] - xa[1]) + rig.c_s * (xa[i0] - xa[n + 1])
            rec["W"][k_out] = W
            rec["T_m"][k_out] = T_m
            rec_stuck[k_out], rec_held[k_out], rec_relief[k_out] = stuck, held, relieving
            k_out += 1

    keep = slice(n_settle, n_out)
    clean = {k: v[keep].copy() for k, v in rec.items()}
    clean["stuck"], clean["held"], clean["relief"] = rec_stuck[keep], rec_held[keep], rec_relief[keep]
    load_cell_raw = rig.k_p * clean["phi_p"] if "platform" in el else clean["T_c"].copy()
    clean["load_cell"] = np.maximum(load_cell_raw, 0.0)
    meas = acquire(clean, p, el, rng, noise, rec["th0"][n_settle - 1], rec["thN"][n_settle - 1])
    return {"time": np.arange(n_rec) / FS, **meas, "clean": clean, "params": p, "elements": sorted(el),
            "f1_clamped_hz": rig.f1_clamped, "k_p": rig.k_p, "beta": rig.beta, "seed": seed, "noise": noise}


# ------------------------------------------------------------------------------------------ acquisition
def _encoder_speed(theta, theta_prev, ppr):
    counts = np.floor(np.concatenate([[theta_prev], theta]) * ppr / (2 * math.pi))
    return np.diff(counts) * (2 * math.pi / ppr) * FS


def _spike(sig, i0, depth_rpm, width, rng):
    """A post-filter encoder spike: ramps from the local value down to depth over `width` samples."""
    i1 = min(sig.size, i0 + width)
    if i1 <= i0:
        return
    ramp = np.linspace(0.0, 1.0, i1 - i0 + 1)[1:]
    sig[i0:i1] = sig[i0:i1] + (depth_rpm * RPM - sig[i0:i1]) * ramp


def acquire(clean, p, el, rng, noise, th0_prev, thN_prev):
    """Sensors, the 10 Hz IIR and the encoder artifacts; returns SI channels."""
    ns = noise if "noise" in el else 0.0
    if "encoders" in el:
        top = _encoder_speed(clean["th0"], th0_prev, p["encoder_ppr"])
        bit = _encoder_speed(clean["thN"], thN_prev, p["encoder_ppr"])
    else:
        top, bit = clean["om0"].copy(), clean["omN"].copy()
    size = top.size
    raw = {"top": top + ns * p["noise_speed"] * rng.standard_normal(size),
           "bit": bit + ns * p["noise_speed"] * rng.standard_normal(size),
           "torque": clean["load_cell"] + ns * p["noise_torque"] * rng.standard_normal(size),
           "wob": clean["W"] + ns * p["noise_wob"] * rng.standard_normal(size)}
    out = {}
    if "iir" in el:
        b, a = scipy.signal.butter(2, p["f_iir"], fs=FS)
        for c, x in raw.items():
            zi = scipy.signal.lfilter_zi(b, a) * x[:20].mean()
            out[c], _ = scipy.signal.lfilter(b, a, x, zi=zi)
    else:
        out = raw
    if ns > 0 and p["noise_top_post"] > 0:
        b, a = scipy.signal.butter(2, 80.0, fs=FS)
        e = scipy.signal.lfilter(b, a, rng.standard_normal(size))
        out["top"] = out["top"] + ns * p["noise_top_post"] * RPM * e / e.std()
    if "artifacts" in el:
        top = out["top"]
        t_end = size / FS
        tk = rng.exponential(1 / p["spike_rate"]) if p["spike_rate"] > 0 else math.inf
        while tk < t_end:
            _spike(top, int(tk * FS), rng.uniform(-220, -100), int(rng.integers(10, 21)), rng)
            tk += rng.exponential(1 / p["spike_rate"])
        st = (clean["om0"] < p["stall_speed"]) & clean["stuck"]
        # a stall shorter than 0.1 s leaves no stretch
        k = int(0.1 * FS)
        st = np.convolve(st.astype(float), np.ones(k), "same") >= k - 0.5
        for a0, a1 in p["stretch"]:
            st[int(a0 * FS):int(a1 * FS)] = True
        idx = np.flatnonzero(st)
        if idx.size:
            top[idx] = (40 + 12 * rng.standard_normal(idx.size)) * RPM
            starts = idx[np.concatenate([[True], np.diff(idx) > 1])]
            ends = idx[np.concatenate([np.diff(idx) > 1, [True]])]
            for s0, s1 in zip(starts, ends):
                j = s0 + int(rng.integers(0, 40))
                while j < s1 - 12:
                    _spike(top, j, rng.uniform(-200, -20), int(rng.integers(8, 13)), rng)
                    j += int(rng.integers(36, 46))
        out["top"] = top
    return {"top_speed": out["top"], "bit_speed": out["bit"], "torque": out["torque"], "wob": out["wob"]}


# ------------------------------------------------------------------------------------------ records
def write_mat(res: dict, path: str) -> None:
    col = lambda x: np.asarray(x, float).reshape(-1, 1)  # noqa: E731
    scipy.io.savemat(path, {"Time" + SUFFIX: col(res["time"]),
                            "Bit_Speed" + SUFFIX: col(res["bit_speed"] / RPM),
                            "Top_Speed" + SUFFIX: col(res["top_speed"] / RPM),
                            "Bit_Torque" + SUFFIX: col(res["torque"]),
                            "WOB" + SUFFIX: col(res["wob"])})
    meta = {"generator": "benchmarks/whole_rig.py (independent of drillpy)", "seed": res["seed"],
            "noise": res["noise"], "elements": res["elements"], "params": res["params"],
            "derived": {"f1_clamped_hz": res["f1_clamped_hz"], "k_p": res["k_p"], "beta": res["beta"],
                        "motor_stall_torque": res["params"]["c_m"] * res["params"]["omega_c"],
                        "static_torque_per_N": res["params"]["mu_static"] * res["params"]["r_b"]},
            "units": {"Time": "s", "Bit_Speed": "RPM", "Top_Speed": "RPM", "Bit_Torque": "N m", "WOB": "N"}}
    Path(path).with_suffix(".json").write_text(json.dumps(meta, indent=1))


def load_mat(path: str):
    d = scipy.io.loadmat(path)
    g = lambda k: d[k + SUFFIX].ravel().astype(float)  # noqa: E731
    return g("Time"), g("Top_Speed") * RPM, g("Bit_Speed") * RPM, g("Bit_Torque"), g("WOB")


# ------------------------------------------------------------------------------------------ statistics
def artifact_mask(top: np.ndarray) -> np.ndarray:
    """Samples near a negative top-speed reading (encoder artifacts), +-80 ms."""
    bad = (top < -1.0).astype(float)
    k = int(0.08 * FS)
    return np.convolve(bad, np.ones(2 * k + 1), "same") > 0


def record_stats(t, top, bit, T, W) -> dict:
    """The figures the brief quotes for sample 175 (SI: rad/s, N m, N)."""
    s = {"top_mean": top.mean(), "top_sd": top.std(), "bit_mean": bit.mean(), "bit_sd": bit.std(),
         "torque_mean": T.mean(), "torque_sd": T.std(), "wob_mean": W.mean(), "wob_sd": W.std()}
    bad = artifact_mask(top)
    s["top_mean_masked"], s["top_sd_masked"], s["masked_fraction"] = top[~bad].mean(), top[~bad].std(), bad.mean()
    f, pw = scipy.signal.welch(bit - bit.mean(), FS, nperseg=8192)
    band = (f > 1) & (f < 6)
    s["peak_hz"] = f[band][np.argmax(pw[band])]
    s["stick_fraction_5pc"] = np.mean(bit < 0.05 * bit.mean())
    s["stick_fraction_10pc"] = np.mean(bit < 0.1 * bit.mean())
    best = None
    for lag in range(0, 151, 2):                    # top(t) on torque(t - lag)
        y, x, m = top[lag:], T[:T.size - lag], ~bad[lag:]
        r = np.corrcoef(x[m], y[m])[0, 1]
        if best is None or r < best[0]:
            b1, b0 = np.polyfit(x[m], y[m], 1)
            best = (r, lag / FS, b0, b1)
    s["droop_r"], s["droop_lag_s"], s["droop_intercept"], s["droop_slope"] = best
    th = np.cumsum(bit) / FS
    deficit = -(th - np.polyval(np.polyfit(t, th, 1), t))
    bh, ah = scipy.signal.butter(2, 0.5, "high", fs=FS)
    dh, wh = scipy.signal.filtfilt(bh, ah, deficit), scipy.signal.filtfilt(bh, ah, W)
    best = None
    for lag in range(-100, 101, 2):                 # W(t) on deficit(t + lag): lag > 0, the WOB leads
        x, y = (dh[lag:], wh[:wh.size - lag]) if lag >= 0 else (dh[:dh.size + lag], wh[-lag:])
        r = np.corrcoef(x, y)[0, 1]
        if best is None or r > best[0]:
            best = (r, lag / FS, np.polyfit(x, y, 1)[0])
    s["wob_deficit_r"], s["wob_lead_s"], s["wob_deficit_slope"] = best
    return {k: float(v) for k, v in s.items()}


STAT_LINES = (("top speed mean / sd [rad/s]", "top_mean", "top_sd"),
              ("  artifacts masked: mean / sd", "top_mean_masked", "top_sd_masked"),
              ("bit speed mean / sd [rad/s]", "bit_mean", "bit_sd"),
              ("torque mean / sd [N m]", "torque_mean", "torque_sd"),
              ("WOB mean / sd [N]", "wob_mean", "wob_sd"),
              ("stick-slip peak [Hz]", "peak_hz", None),
              ("stick fraction (<5 % / <10 % of mean)", "stick_fraction_5pc", "stick_fraction_10pc"),
              ("droop: top = a + b T: a [rad/s], b", "droop_intercept", "droop_slope"),
              ("droop: corr, top lag [s]", "droop_r", "droop_lag_s"),
              ("WOB_hp vs deficit: corr, lead [s]", "wob_deficit_r", "wob_lead_s"),
              ("WOB_hp vs deficit: slope [N/rad]", "wob_deficit_slope", None))


def format_stats(cols: dict) -> str:
    names = list(cols)
    out = [f"{'':40s}" + "".join(f"{n:>22s}" for n in names)]
    for label, a, b in STAT_LINES:
        row = f"{label:40s}"
        for n in names:
            s = cols[n]
            row += f"{s[a]:>11.3f}" + (f"{s[b]:>11.3f}" if b else f"{'':>11s}")
        out.append(row)
    return "\n".join(out)


# ------------------------------------------------------------------------------------------ CLI
def _parse_value(v: str):
    try:
        return json.loads(v)
    except json.JSONDecodeError:
        return v


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", help=".mat file to write (and its .json beside it)")
    ap.add_argument("--duration", type=float, default=40.0)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--noise", type=float, default=1.0, help="sensor-noise factor")
    ap.add_argument("--effects", default="all", help="comma-separated elements to switch on (all: "
                    + ", ".join(ELEMENTS) + ")")
    ap.add_argument("--without", default="", help="comma-separated elements to switch off")
    ap.add_argument("--set", action="append", default=[], metavar="PAR=VALUE",
                    help="override a parameter (SI), e.g. mu_static=1.2 or stretch=[[28,30]]")
    ap.add_argument("--stats", action="store_true", help="print the record's statistics (next to sample 175's)")
    ap.add_argument("--stats-of", help="print the statistics of a .mat record of this format and exit")
    ap.add_argument("--reference", default=str(Path(__file__).resolve().parents[2] / "shared" / "data" /
                                               "testrig" / "sample175_0-40s.mat"))
    a = ap.parse_args(argv)
    if a.stats_of:
        print(format_stats({Path(a.stats_of).stem[:20]: record_stats(*load_mat(a.stats_of))}))
        return 0
    el = set(ELEMENTS) if a.effects == "all" else {x for x in a.effects.split(",") if x}
    el -= {x for x in a.without.split(",") if x}
    unknown = (el | {x for x in a.without.split(",") if x}) - set(ELEMENTS)
    if unknown:
        ap.error(f"unknown elements {sorted(unknown)} (known: {', '.join(ELEMENTS)})")
    over = {}
    for s in a.set:
        k, v = s.split("=", 1)
        if k not in DEFAULTS:
            ap.error(f"unknown parameter {k}")
        over[k] = _parse_value(v)
    t0 = time.process_time()
    res = simulate(over, el, duration=a.duration, seed=a.seed, noise=a.noise)
    cpu = time.process_time() - t0
    if a.out:
        write_mat(res, a.out)
    if a.stats or not a.out:
        cols = {"whole_rig": record_stats(res["time"], res["top_speed"], res["bit_speed"], res["torque"],
                                          res["wob"])}
        if Path(a.reference).is_file():
            cols["sample 175"] = record_stats(*load_mat(a.reference))
        print(format_stats(cols))
        c = res["clean"]
        print(f"clean: stuck {c['stuck'].mean():.3f}, top held {c['held'].mean():.3f}, relief "
              f"{c['relief'].mean():.3f}, contact torque max {c['T_c'].max():.2f} N m, f1 (top clamped) "
              f"{res['f1_clamped_hz']:.2f} Hz; cpu {cpu:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
